"""The sim2d node: steps the core simulator against a wall-clock timer and publishes in sim time.

Scheduling: a steady (wall) timer runs as many physics steps as ``real_time_factor`` demands (or,
with 0, as many as fit in a short wall budget); after each step the node publishes whatever is due
in sim time: /clock at ``clock_rate``, /odom + /tf + ground_truth at ``odometry.rate``, /scan at
``lidar.rate``, /battery_state at ``battery_rate`` (and at once when charging on a dock starts or
stops: Nav2's docking server waits only ``wait_charge_timeout``, 5 s, for it), detected_dock_pose at
``dock_detection.rate`` while a dock's tag is in view. Every stamp is sim time; /clock is the source.

Lockstep (``lockstep.enabled``): the participants' reports on /lockstep/progress feed a
:class:`~sim2d.core.lockstep.LockstepGate`, and no step goes beyond its limit (the slowest report
plus ``lockstep.max_lead``); the real-time factor still caps the speed on top. When the gate
blocks, the sim sends /clock at its current time and cancels the stepping timer (no busy wait); a
progress report that moves the limit steps on at once, in its own callback, and restarts the timer
only if that burst does not reach the limit again. A 0.1 s wall watchdog re-sends /clock while
blocked (participants answer a repeated /clock with a report, late joiners learn the time), drops
the participants silent for ``lockstep.timeout`` (or DEAD_GRACE once their process is gone) with
one warning each, and lets the sim go on.
In max mode (``real_time_factor`` 0) the stepping timer fires every 1 ms and each burst stops
after 20 ms of wall time, so cmd_vel and progress callbacks get their turn in between.

ROS surface (names relative to the node namespace unless absolute):
  sub  cmd_vel (geometry_msgs/Twist, or TwistStamped with enable_stamped_cmd_vel; a stamped command
       takes effect at stamp + stamped_cmd_vel_delay of sim time, sim2d/core/command_schedule.py)
  sub  sim2d/teleport, sim2d/lidar_dropout, sim2d/spawn_obstacle: act on the world (world_inputs.py)
  sub  sim2d/odometry_slip, sim2d/topic_loss: faults of the robot's outputs (fault_inputs.py)
  sub  /lockstep/progress (std_msgs/Header, only with lockstep.enabled)
  pub  /clock, scan (reliable), odom, /tf, /tf_static (transient local), ground_truth (frame map),
       battery_state, sim2d/collisions (PointStamped per new contact),
       detected_dock_pose (geometry_msgs/PoseStamped, the seen dock's tag in base_link; only in a world
       with docks, only while a tag is seen: sim2d/core/dock_detection.py),
       sim2d/collision_count (UInt32, transient local), sim2d/real_time_factor (Float64, achieved),
       sim2d/clearance (Float64, m: the true gap between the robot's footprint and the nearest obstacle,
       with each odom while someone subscribes; sim2d/core/clearance.py)
  srv  sim2d/reset (std_srvs/Empty), sim2d/pause (std_srvs/SetBool: true pauses)
"""

from __future__ import annotations

import math
import time

import numpy as np
from geometry_msgs.msg import PointStamped, PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock as ClockMsg
from sensor_msgs.msg import BatteryState, LaserScan
from std_msgs.msg import Float64, Header, UInt32
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage

from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC, REPORT_PERIOD
from sim2d.core.clearance import simulator_clearance
from sim2d.core.command_schedule import CommandSchedule
from sim2d.core.lockstep import LockstepGate
from sim2d.core.robot import robot_model
from sim2d.core.simulator import Simulator
from sim2d.core.world import load_world
from sim2d.ros import messages
from sim2d.ros.config import NODE_NAME, SimConfig, build_config, declare_all
from sim2d.ros.fault_inputs import FaultInputs
from sim2d.ros.world_inputs import LIDAR_DROPOUT_TOPIC, SPAWN_OBSTACLE_TOPIC, TELEPORT_TOPIC, WorldInputs

__all__ = ["LIDAR_DROPOUT_TOPIC", "SPAWN_OBSTACLE_TOPIC", "TELEPORT_TOPIC", "Sim2dNode"]

CLOCK_TOPIC, TF_TOPIC, TF_STATIC_TOPIC = "/clock", "/tf", "/tf_static"
SCAN_TOPIC, ODOM_TOPIC, CMD_VEL_TOPIC = "scan", "odom", "cmd_vel"
GROUND_TRUTH_TOPIC, BATTERY_TOPIC = "ground_truth", "battery_state"
COLLISIONS_TOPIC, COLLISION_COUNT_TOPIC = "sim2d/collisions", "sim2d/collision_count"
RTF_TOPIC = "sim2d/real_time_factor"
CLEARANCE_TOPIC = "sim2d/clearance"
DETECTED_DOCK_TOPIC = "detected_dock_pose"   # opennav_docking SimpleChargingDock's subscription
RESET_SERVICE, PAUSE_SERVICE = "sim2d/reset", "sim2d/pause"

TICK_PERIOD = 0.005        # wall seconds between stepping bursts
MAX_MODE_TICK = 0.001      # wall seconds between bursts in max mode: the executor serves inputs in between
MAX_MODE_BUDGET = 0.02     # wall seconds of stepping per burst (cmd_vel and progress wait at most this)
MAX_LAG = 0.25             # sim seconds of backlog dropped rather than caught up in a burst
WATCHDOG_PERIOD = 0.1      # wall seconds between lockstep checks (timeouts, repeated /clock)
DEAD_GRACE = 1.0           # wall seconds of silence before a participant whose process is gone is dropped

RELIABLE_10 = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
#: /clock keeps a burst's worth of ticks for its reliable readers: one stepping burst can reach MAX_LAG
#: (0.25 s, 25 ticks at 100 Hz), and with a history of 10 a reader whose process was busy lost the
#: ticks the writer had already dropped (CI run DJ: 189 of 200 in a test's window).
CLOCK_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _period_ns(rate: float) -> int:
    return max(1, round(1e9 / rate))


class Sim2dNode(Node):
    """One simulated robot (``robot`` parameter: waffle, burger or tb4) on the ROS graph."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)  # type: ignore[arg-type]
        dynamic = ParameterDescriptor(dynamic_typing=True)
        values = declare_all(lambda name, default: self.declare_parameter(name, default, dynamic).value)
        self.config: SimConfig = build_config(values)
        cfg = self.config
        self.robot = robot_model(cfg.node.robot)
        world = load_world(cfg.node.world)
        self.sim = Simulator(world, self.robot, cfg.sim, np.random.default_rng(cfg.node.seed),
                             cfg.lidar, cfg.odometry, cfg.battery, cfg.collision, cfg.dock_detection)
        self.paused = False
        self.achieved_rtf = 0.0
        self.commands = CommandSchedule(round(cfg.node.stamped_cmd_vel_delay * 1e9))
        self._late_warned = 0
        self._warned: set[tuple[str, str]] = set()
        self._make_interfaces()
        self._periods = {"clock": _period_ns(cfg.node.clock_rate), "odom": _period_ns(cfg.odometry.rate),
                         "scan": _period_ns(cfg.lidar.rate), "battery": _period_ns(cfg.node.battery_rate),
                         "dock": _period_ns(cfg.dock_detection.rate)}
        self._due = dict.fromkeys(self._periods, 0)
        self._clock_sent = (-1, time.monotonic())     # (sim ns, wall s) of the newest /clock sent
        self._battery_was_empty = False  # before the first publish: it warns about a battery empty at start
        self._charging_reported = False  # battery.charging in the newest /battery_state
        self._publish_due()
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._anchor = (time.monotonic(), self.sim.time_ns)
        self._rtf_window = (time.monotonic(), self.sim.time_ns)
        self._last_log = time.monotonic()
        self._step_timer = self.create_timer(TICK_PERIOD if cfg.node.real_time_factor > 0 else MAX_MODE_TICK,
                                             self._tick, clock=wall)
        self.create_timer(1.0, self._report_rtf, clock=wall)
        self.create_timer(2.0, self._check_cmd_vel_types, clock=wall)
        rtf = cfg.node.real_time_factor
        self.get_logger().info(
            f"sim2d: world {world.name} ({world.source}), robot {self.robot.name}, spawn "
            f"({cfg.sim.initial_pose.x}, {cfg.sim.initial_pose.y}, {cfg.sim.initial_pose.yaw}), "
            f"real-time factor {'max' if rtf == 0 else rtf}, step {cfg.sim.physics_step} s; charging "
            + (f"on the docks {', '.join(dock.id for dock in world.docks) or '(none in this world)'}"
               if self.sim.battery.uses_docks else f"within {cfg.battery.station_radius} m of the station"))
        self.gate: LockstepGate | None = None
        self._blocked = False
        if cfg.lockstep.enabled:
            self._start_lockstep(wall)

    def _make_interfaces(self) -> None:
        cfg = self.config
        self.pub_clock = self.create_publisher(ClockMsg, CLOCK_TOPIC, CLOCK_QOS)
        self.pub_scan = self.create_publisher(LaserScan, SCAN_TOPIC, RELIABLE_10)
        self.pub_odom = self.create_publisher(Odometry, ODOM_TOPIC, RELIABLE_10)
        self.pub_truth = self.create_publisher(Odometry, GROUND_TRUTH_TOPIC, RELIABLE_10)
        self.pub_tf = self.create_publisher(TFMessage, TF_TOPIC, QoSProfile(depth=100))
        self.pub_tf_static = self.create_publisher(TFMessage, TF_STATIC_TOPIC, LATCHED)
        self.pub_battery = self.create_publisher(BatteryState, BATTERY_TOPIC, RELIABLE_10)
        self.pub_collision = self.create_publisher(PointStamped, COLLISIONS_TOPIC, RELIABLE_10)
        self.pub_collision_count = self.create_publisher(UInt32, COLLISION_COUNT_TOPIC, LATCHED)
        self.pub_rtf = self.create_publisher(Float64, RTF_TOPIC, RELIABLE_10)
        self.pub_clearance = self.create_publisher(Float64, CLEARANCE_TOPIC, RELIABLE_10)
        self.pub_dock = self.create_publisher(PoseStamped, DETECTED_DOCK_TOPIC, RELIABLE_10) \
            if self.sim.docks else None
        self._cmd_type = TwistStamped if cfg.node.enable_stamped_cmd_vel else Twist
        self.create_subscription(self._cmd_type, CMD_VEL_TOPIC, self._on_cmd_vel, RELIABLE_10)
        self.world_inputs = WorldInputs(self, self.sim, RELIABLE_10)
        self.fault_inputs = FaultInputs(self, self.sim, RELIABLE_10)
        self.create_service(Empty, RESET_SERVICE, self._on_reset)
        self.create_service(SetBool, PAUSE_SERVICE, self._on_pause)
        self._odom = messages.OdometryBuilder(messages.ODOM_FRAME)
        self._truth = messages.OdometryBuilder(messages.MAP_FRAME)
        self._tf = messages.TfBuilder()
        self._scan = messages.ScanBuilder(cfg.lidar, self.robot.scan_frame)
        self.pub_tf_static.publish(messages.static_transforms(self.robot, 0))
        self.pub_collision_count.publish(UInt32(data=0))

    # ------------------------------------------------------------------ stepping
    def _tick(self) -> None:
        """Step as far as the real-time factor, the lockstep gate and one wall budget allow."""
        if self.paused:
            return
        started = time.monotonic()
        sim = self.sim
        target = self._paced_target(started)
        limit = self._lockstep_limit(started)
        if limit is not None:
            target = limit if target is None else min(target, limit)
        while target is None or sim.time_ns + sim.step_ns <= target:
            self._step()
            if time.monotonic() - started > MAX_MODE_BUDGET:
                break
        if limit is not None and sim.time_ns + sim.step_ns > limit:
            self._block()

    def _paced_target(self, wall_now: float) -> int | None:
        """The sim time (ns) ``real_time_factor`` asks for at ``wall_now``; None in max mode."""
        rtf = self.config.node.real_time_factor
        if rtf <= 0:
            return None
        wall0, sim0 = self._anchor
        target = sim0 + int((wall_now - wall0) * rtf * 1e9)
        if target - self.sim.time_ns > MAX_LAG * 1e9:     # fell behind: drop the debt, report lower RTF
            target = self.sim.time_ns + int(MAX_LAG * 1e9)
            self._anchor = (wall_now, target)
        return target

    def _step(self) -> None:
        for command in self.commands.due(self.sim.time_ns):   # stamped commands whose time has come
            self.sim.command(command.v, command.w)
        self.sim.step()
        self._publish_due()

    def _publish_clock(self, now_ns: int) -> None:
        self.pub_clock.publish(messages.clock(now_ns))
        self._clock_sent = (now_ns, time.monotonic())

    def _publish_due(self) -> None:
        now, due, sim = self.sim.time_ns, self._due, self.sim
        lost = sim.topic_loss.lost  # a topic loss event (fault_inputs.py): its messages are not sent
        if now >= due["odom"]:
            odom = sim.odometry
            if not lost(ODOM_TOPIC, now):
                self.pub_odom.publish(self._odom.build(now, odom.pose, sim.v, sim.w, odom.variance_trans,
                                                       odom.variance_rot))
            if not lost("tf", now):
                self.pub_tf.publish(self._tf.build(now, odom.pose))
            self.pub_truth.publish(self._truth.build(now, sim.pose, sim.v, sim.w, 0.0, 0.0))
            # at the odometry rate, not every physics step, and only for a listener: one evaluation costs
            # about 20 physics steps (bench/bench_clearance.py)
            if self.pub_clearance.get_subscription_count() > 0:
                self.pub_clearance.publish(Float64(data=simulator_clearance(sim)))
            due["odom"] = self._next_due(due["odom"], self._periods["odom"], now)
        if now >= due["scan"]:
            ranges = sim.scan()  # taken even when lost: the lidar's noise stream stays the same
            if not lost(SCAN_TOPIC, now):
                self.pub_scan.publish(self._scan.build(now, ranges))
            due["scan"] = self._next_due(due["scan"], self._periods["scan"], now)
        if self.pub_dock is not None and now >= due["dock"]:
            detection = sim.detect_dock()
            if detection is not None:
                self.pub_dock.publish(messages.detected_dock_pose(now, detection))
            due["dock"] = self._next_due(due["dock"], self._periods["dock"], now)
        dock_change = sim.battery.uses_docks and sim.battery.charging != self._charging_reported
        if now >= due["battery"] or dock_change:
            if not lost(BATTERY_TOPIC, now):
                self.pub_battery.publish(messages.battery_state(now, sim.battery))
            if dock_change:
                self._log_dock_change()
            self._charging_reported = sim.battery.charging
            if now >= due["battery"]:
                due["battery"] = self._next_due(due["battery"], self._periods["battery"], now)
            self._warn_if_battery_empty(sim.battery.empty)
        if sim.collision_events:
            for event in sim.pop_collision_events():
                self.pub_collision.publish(messages.collision_point(event.time_ns, event.x, event.y))
            self.pub_collision_count.publish(UInt32(data=sim.collision_count))
        # /clock last: a participant that takes /clock t off its queue has every message stamped up
        # to t queued before it, so its timers due at t see the same data on every run.
        if now >= due["clock"]:
            self._publish_clock(now)
            due["clock"] = self._next_due(due["clock"], self._periods["clock"], now)

    def _log_dock_change(self) -> None:
        """Say when charging on a dock starts or stops, and where the robot stands against the dock."""
        sim = self.sim
        if sim.battery.charging and sim.docked is not None:
            dock = sim.docked
            offset_mm = 1000.0 * math.hypot(sim.pose.x - dock.pose.x, sim.pose.y - dock.pose.y)
            self.get_logger().info(
                f"sim2d: charging on {dock.id} at sim time {sim.time:.3f} s (base_link {offset_mm:.0f} mm "
                f"from its contact pose, {sim.battery.current:.1f} A)")
        else:
            self.get_logger().info(f"sim2d: charging stopped at sim time {sim.time:.3f} s")

    def _warn_if_battery_empty(self, empty: bool) -> None:
        """Say once why the robot stopped obeying cmd_vel; say again after a recharge empties it again."""
        if empty and not self._battery_was_empty:
            battery = self.sim.battery
            p = battery.params
            where = (f"on a dock ({', '.join(dock.id for dock in self.sim.docks) or 'the world has none'})"
                     if battery.uses_docks else
                     f"within {p.station_radius} m of the station ({p.station_x}, {p.station_y})")
            self.get_logger().warn(
                f"battery empty at sim time {self.sim.time:.1f} s: the robot ignores cmd_vel until it is "
                f"recharged {where}; set battery.drain_per_meter and battery.drain_per_second to 0 to "
                "drive forever")
        self._battery_was_empty = empty

    @staticmethod
    def _next_due(due: int, period: int, now: int) -> int:
        """Next slot on the fixed grid of ``period``: the average rate is exact whatever the step."""
        due += period
        return due if due > now else now + period

    def _report_rtf(self) -> None:
        wall_now = time.monotonic()
        wall0, sim0 = self._rtf_window
        achieved = (self.sim.time_ns - sim0) * 1e-9 / max(wall_now - wall0, 1e-9)
        self._rtf_window = (wall_now, self.sim.time_ns)
        self.achieved_rtf = achieved
        self.pub_rtf.publish(Float64(data=achieved))
        if wall_now - self._last_log >= self.config.node.rtf_log_period:
            self._last_log = wall_now
            target = self.config.node.real_time_factor
            self.get_logger().info(f"sim2d: real-time factor {achieved:.1f} (target "
                                   f"{'max' if target == 0 else target}), sim time {self.sim.time:.1f} s")

    # ------------------------------------------------------------------ lockstep
    def _start_lockstep(self, wall: Clock) -> None:
        cfg = self.config.lockstep
        now = time.monotonic()
        self.gate = LockstepGate(round(cfg.max_lead * 1e9), cfg.timeout, now, cfg.participants,
                                 cfg.startup_timeout, DEAD_GRACE)
        self.create_subscription(Header, PROGRESS_TOPIC, self._on_progress, PROGRESS_QOS)
        self.create_timer(WATCHDOG_PERIOD, self._lockstep_watchdog, clock=wall)
        waits = "waits for no role before stepping"
        if cfg.participants:
            waits = (f"waits for {', '.join(cfg.participants)} before the first step "
                     f"(at most {cfg.startup_timeout} s wall)")
        self.get_logger().info(
            f"sim2d: lockstep on: at most {cfg.max_lead} s of sim time ahead of the slowest participant "
            f"on {PROGRESS_TOPIC}; {waits}; a participant silent for {cfg.timeout} s wall, or for "
            f"{DEAD_GRACE} s once its process is gone, is dropped")
        if cfg.max_lead < REPORT_PERIOD + 1.0 / self.config.node.clock_rate:
            self.get_logger().warning(
                f"sim2d: lockstep.max_lead {cfg.max_lead} s is under one participant report period plus one "
                f"clock period ({REPORT_PERIOD} + {1.0 / self.config.node.clock_rate} s): the sim will often "
                f"wait for the {WATCHDOG_PERIOD} s watchdog")

    def _lockstep_limit(self, wall_now: float) -> int | None:
        """The gate's limit (ns), or None without lockstep; warns once about each dropped participant."""
        if self.gate is None:
            return None
        limit = self.gate.limit_ns(wall_now)
        cfg = self.config.lockstep
        for dropped in self.gate.take_dropped():     # named with the configured timeout they exceeded
            if dropped.name is None:
                self.get_logger().warning(
                    f"lockstep: {dropped.role} has not reported within {cfg.startup_timeout} s wall "
                    "(lockstep.startup_timeout); the simulator goes on without it")
            elif dropped.awaited:
                self.get_logger().warning(
                    f"lockstep: {dropped.role} ({dropped.name}) is gone (its process has exited without "
                    f"leaving); the simulator holds until a new {dropped.role} process joins (a respawn), "
                    f"at most {cfg.startup_timeout} s wall (lockstep.startup_timeout)")
            elif dropped.gone:
                self.get_logger().warning(
                    f"lockstep: {dropped.role} ({dropped.name}) is gone (its process has exited without "
                    "leaving); the simulator goes on without it")
            else:
                self.get_logger().warning(
                    f"lockstep: {dropped.role} ({dropped.name}) has not reported for {cfg.timeout} s wall; "
                    "the simulator goes on without it")
        return limit

    def _block(self) -> None:
        """Stop stepping until a report moves the limit; make sure the participants saw the newest time."""
        self._blocked = True
        self._step_timer.cancel()
        if self._clock_sent[0] < self.sim.time_ns:
            self._publish_clock(self.sim.time_ns)

    def _unblock_if_free(self, wall_now: float) -> None:
        """Step on at once if the limit has moved past the next step.

        The stepping timer is reset only when one burst does not reach the limit again: resetting it
        on every report (thousands per second) keeps the EventsExecutor's timer manager re-arming
        and starves the other timers (the watchdog, the real-time factor) for seconds.
        """
        limit = self._lockstep_limit(wall_now)
        if limit is not None and self.sim.time_ns + self.sim.step_ns > limit:
            return
        self._blocked = False
        self._anchor = (wall_now, self.sim.time_ns)   # the waiting is not a debt to catch up
        self._tick()                # now, not a timer period later
        if not self._blocked:
            self._step_timer.reset()

    def _on_progress(self, msg: Header) -> None:
        if self.gate is None:
            return
        wall_now = time.monotonic()
        stamp_ns = msg.stamp.sec * 1_000_000_000 + msg.stamp.nanosec
        waiting = self.gate.waiting_for
        if self.gate.report(msg.frame_id, stamp_ns, wall_now):
            self.get_logger().info(f"lockstep: {msg.frame_id} joined at sim time {self.sim.time:.3f} s")
        if waiting and not self.gate.waiting_for:
            self.get_logger().info(f"lockstep: every expected role has joined ({', '.join(sorted(waiting))} "
                                   "last); the simulator starts stepping")
        if self._blocked and not self.paused:
            self._unblock_if_free(wall_now)

    def _lockstep_watchdog(self) -> None:
        """Timeouts and repeated /clock while blocked (participants answer it with a report)."""
        if self.paused:
            return
        wall_now = time.monotonic()
        if self._blocked:
            self._unblock_if_free(wall_now)
        else:
            self._lockstep_limit(wall_now)
        if self._blocked or wall_now - self._clock_sent[1] >= WATCHDOG_PERIOD:
            self._publish_clock(self.sim.time_ns)

    # ------------------------------------------------------------------ inputs
    def _on_cmd_vel(self, msg: Twist | TwistStamped) -> None:
        if isinstance(msg, Twist):
            self.sim.command(msg.linear.x, msg.angular.z)
            return
        twist, stamp_ns = msg.twist, msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        if stamp_ns == 0 or self.commands.delay_ns == 0:   # unstamped in all but type: on arrival
            self.sim.command(twist.linear.x, twist.angular.z)
            return
        self.commands.add(stamp_ns, twist.linear.x, twist.angular.z, self.sim.time_ns)
        if self.commands.late > self._late_warned:
            self._warn_late()

    def _warn_late(self) -> None:
        """Say (at most every 100 late commands) that stamped commands arrive after their time."""
        if self._late_warned and self.commands.late < self._late_warned + 100:
            return
        self._late_warned = self.commands.late
        self.get_logger().warning(
            f"sim2d: {self.commands.late} stamped cmd_vel arrived after stamp + stamped_cmd_vel_delay "
            f"({self.config.node.stamped_cmd_vel_delay} s; worst {self.commands.worst_late_ns * 1e-9:.3f} s "
            "late) and took effect on arrival: runs are not exact repeats; raise the delay")

    def _check_cmd_vel_types(self) -> None:
        """Warn once per publisher whose cmd_vel type is not the one this node subscribes to."""
        topic = self.resolve_topic_name(CMD_VEL_TOPIC)
        expected = "geometry_msgs/msg/TwistStamped" if self._cmd_type is TwistStamped \
            else "geometry_msgs/msg/Twist"
        for info in self.get_publishers_info_by_topic(topic):
            key = (f"{info.node_namespace.rstrip('/')}/{info.node_name}", info.topic_type)
            if info.topic_type != expected and key not in self._warned:
                self._warned.add(key)
                self.get_logger().warning(
                    f"sim2d: {key[0]} publishes {info.topic_type} on {topic}, but sim2d expects {expected} "
                    f"(enable_stamped_cmd_vel={self.config.node.enable_stamped_cmd_vel}); "
                    "its commands are ignored")

    def _on_reset(self, request: Empty.Request, response: Empty.Response) -> Empty.Response:
        self.sim.reset()
        self.commands.clear()
        self.pub_collision_count.publish(UInt32(data=0))
        self.get_logger().info("sim2d: reset to the spawn pose")
        return response

    def _on_pause(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        self.paused = bool(request.data)
        wall_now = time.monotonic()
        if self.gate is not None:       # silence while paused counts against nobody
            if self.paused:
                self.gate.suspend(wall_now)
            else:
                self.gate.resume(wall_now)
        if not self.paused:
            self._anchor = (wall_now, self.sim.time_ns)   # resume without catching up
            if self._blocked:
                self._unblock_if_free(wall_now)
        response.success = True
        response.message = "paused" if self.paused else "running"
        return response
