"""The sim2d node: steps the core simulator against a wall-clock timer and publishes in sim time.

Scheduling: a steady (wall) timer runs as many physics steps as ``real_time_factor`` demands (or,
with 0, as many as fit in a short wall budget); after each step the node publishes whatever is due
in sim time: each robot's outputs (robot_outputs.py: odom + tf + ground_truth at ``odometry.rate``,
scan at ``lidar.rate``, battery_state at ``battery_rate`` and when charging on a dock starts or
stops, detected_dock_pose at ``dock_detection.rate`` while a tag is in view), then /clock at
``clock_rate``. Every stamp is sim time; /clock is the source.

One robot or a fleet (issue 48): with the ``fleet`` parameter empty the node runs one Simulator
(``robot`` at ``initial_pose``) on the un-namespaced topics below. With a fleet (config.py:
``name:model:x,y,yaw`` entries) it runs one sim2d.core.fleet.Fleet, and every robot has the same
outputs and robot inputs under its name (/robot1/scan, /robot1/cmd_vel, TF on /robot1/tf and
/robot1/tf_static with unprefixed frame ids, as Nav2's multi-robot bringup remaps /tf to tf). What
the world has once stays un-namespaced: /clock, sim2d/spawn_obstacle, sim2d/real_time_factor,
sim2d/reset and sim2d/pause (every robot), and lockstep. A robot-robot contact is a collision event
on both robots' sim2d/collisions, and a log line names both.

Lockstep (``lockstep.enabled``): the participants' reports on /lockstep/progress feed a
:class:`~sim2d.core.lockstep.LockstepGate`, and no step goes beyond its limit (the slowest report
plus ``lockstep.max_lead``); the real-time factor still caps the speed on top. A fleet's stacks
report with roles such as ``robot1/nav2`` (``lockstep.participants: [robot1/nav2, robot2/nav2]``):
a role is any text without ':', the separator of the role from the pid. When the gate
blocks, the sim sends /clock at its current time and cancels the stepping timer (no busy wait); a
progress report that moves the limit steps on at once, in its own callback, and restarts the timer
only if that burst does not reach the limit again. A 0.1 s wall watchdog re-sends /clock while
blocked (participants answer a repeated /clock with a report, late joiners learn the time), drops
the participants silent for ``lockstep.timeout`` (or DEAD_GRACE once their process is gone) with
one warning each, and lets the sim go on.
In max mode (``real_time_factor`` 0) the stepping timer fires every 1 ms and each burst stops
after 20 ms of wall time, so cmd_vel and progress callbacks get their turn in between.

ROS surface (names relative to the node namespace unless absolute; <r>/ is "" for a robot alone and
the robot's name in a fleet):
  sub  <r>/cmd_vel (geometry_msgs/Twist, or TwistStamped with enable_stamped_cmd_vel; a stamped command
       takes effect at stamp + stamped_cmd_vel_delay of sim time, sim2d/core/command_schedule.py)
  sub  <r>/sim2d/teleport, <r>/sim2d/lidar_dropout, sim2d/spawn_obstacle: act on the world (world_inputs.py)
  sub  <r>/sim2d/odometry_slip, <r>/sim2d/topic_loss: faults of the robot's outputs (fault_inputs.py)
  sub  /lockstep/progress (std_msgs/Header, only with lockstep.enabled)
  pub  /clock, sim2d/real_time_factor (Float64, achieved)
  pub  <r>/scan (reliable), <r>/odom, /tf and /tf_static (transient local; <r>/tf and <r>/tf_static in
       a fleet), <r>/ground_truth (frame map), <r>/battery_state, <r>/sim2d/collisions (PointStamped per
       new contact), <r>/detected_dock_pose (geometry_msgs/PoseStamped, the seen dock's tag in base_link;
       only in a world with docks, only while a tag is seen: sim2d/core/dock_detection.py),
       <r>/sim2d/collision_count (UInt32, transient local), <r>/sim2d/clearance (Float64, m: the true
       gap between the robot's footprint and the nearest obstacle of the world, with each odom while
       someone subscribes; sim2d/core/clearance.py); robot_outputs.py has the details
  srv  sim2d/reset (std_srvs/Empty: every robot), sim2d/pause (std_srvs/SetBool: true pauses)
"""

from __future__ import annotations

import functools
import time

import numpy as np
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock as ClockMsg
from std_msgs.msg import Float64, Header
from std_srvs.srv import Empty, SetBool

from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC, REPORT_PERIOD
from sim2d.core.fleet import Fleet
from sim2d.core.lockstep import LockstepGate
from sim2d.core.robot import robot_model
from sim2d.core.simulator import RobotSim, Simulator
from sim2d.core.world import World, load_world
from sim2d.ros import messages
from sim2d.ros.config import NODE_NAME, SimConfig, build_config, declare_all, fleet_robots
from sim2d.ros.fault_inputs import FaultInputs
from sim2d.ros.robot_outputs import RELIABLE_10, RobotOutputs, next_due, period_ns
from sim2d.ros.world_inputs import (
    LIDAR_DROPOUT_TOPIC,
    ROBOT_TOPICS,
    SPAWN_OBSTACLE_TOPIC,
    TELEPORT_TOPIC,
    FleetMember,
    WorldInputs,
)

__all__ = ["LIDAR_DROPOUT_TOPIC", "SPAWN_OBSTACLE_TOPIC", "TELEPORT_TOPIC", "Sim2dNode"]

CLOCK_TOPIC = "/clock"
RTF_TOPIC = "sim2d/real_time_factor"
RESET_SERVICE, PAUSE_SERVICE = "sim2d/reset", "sim2d/pause"

TICK_PERIOD = 0.005        # wall seconds between stepping bursts
MAX_MODE_TICK = 0.001      # wall seconds between bursts in max mode: the executor serves inputs in between
MAX_MODE_BUDGET = 0.02     # wall seconds of stepping per burst (cmd_vel and progress wait at most this)
MAX_LAG = 0.25             # sim seconds of backlog dropped rather than caught up in a burst
WATCHDOG_PERIOD = 0.1      # wall seconds between lockstep checks (timeouts, repeated /clock)
DEAD_GRACE = 1.0           # wall seconds of silence before a participant whose process is gone is dropped

#: /clock keeps a burst's worth of ticks for its reliable readers: one stepping burst can reach MAX_LAG
#: (0.25 s, 25 ticks at 100 Hz), and with a history of 10 a reader whose process was busy lost the
#: ticks the writer had already dropped (CI run DJ: 189 of 200 in a test's window).
CLOCK_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


class Sim2dNode(Node):
    """One simulated robot (``robot``: waffle, burger or tb4), or a fleet (``fleet``), on the ROS graph.

    Attributes:
        sim: the robot alone; in a fleet, its first robot (``fleet.robots`` has them all).
        robot: ``sim``'s model.
        fleet: the Fleet, or None for a robot alone.
        outputs: each robot's outputs (robot_outputs.py), in the fleet's order.
    """

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)  # type: ignore[arg-type]
        dynamic = ParameterDescriptor(dynamic_typing=True)
        values = declare_all(lambda name, default: self.declare_parameter(name, default, dynamic).value)
        self.config: SimConfig = build_config(values)
        cfg = self.config
        world = load_world(cfg.node.world)
        rng = np.random.default_rng(cfg.node.seed)
        self.fleet: Fleet | None = None
        if cfg.node.fleet:
            self.fleet = Fleet(world, fleet_robots(cfg), cfg.sim, rng, None, cfg.odometry, cfg.battery,
                               cfg.collision, cfg.dock_detection)
            robots: dict[str, RobotSim] = dict(self.fleet.robots)
            self.world_sim: Simulator | Fleet = self.fleet
        else:
            lone = Simulator(world, robot_model(cfg.node.robot), cfg.sim, rng, cfg.lidar, cfg.odometry,
                             cfg.battery, cfg.collision, cfg.dock_detection)
            robots = {"": lone}
            self.world_sim = lone
        self.sim: RobotSim = next(iter(robots.values()))
        self.robot = self.sim.robot
        self.paused = False
        self._warned: set[tuple[str, str]] = set()   # (publisher node, type) warned about on a cmd_vel
        self._make_interfaces(robots)
        self._clock_period, self._clock_due = period_ns(cfg.node.clock_rate), 0
        self._clock_sent = (-1, time.monotonic())     # (sim ns, wall s) of the newest /clock sent
        self._publish_due()
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._anchor = (time.monotonic(), self.world_sim.time_ns)
        self._rtf_window = (time.monotonic(), self.world_sim.time_ns)
        self._last_log = time.monotonic()
        self._step_timer = self.create_timer(TICK_PERIOD if cfg.node.real_time_factor > 0 else MAX_MODE_TICK,
                                             self._tick, clock=wall)
        self.create_timer(1.0, self._report_rtf, clock=wall)
        self.create_timer(2.0, self._check_cmd_vel_types, clock=wall)
        self._log_start(world)
        self.gate: LockstepGate | None = None
        self._blocked = False
        if cfg.lockstep.enabled:
            self._start_lockstep(wall)

    def _make_interfaces(self, robots: dict[str, RobotSim]) -> None:
        """Each robot's outputs and inputs (namespaced by its name in a fleet), then the world's."""
        self.pub_clock = self.create_publisher(ClockMsg, CLOCK_TOPIC, CLOCK_QOS)
        self.pub_rtf = self.create_publisher(Float64, RTF_TOPIC, RELIABLE_10)
        self.outputs: list[RobotOutputs] = []
        self.inputs: list[WorldInputs | FaultInputs] = []
        for name, sim in robots.items():
            scan = sim.scan if self.fleet is None else functools.partial(self.fleet.scan, name)
            self.outputs.append(RobotOutputs(self, sim, self.config, scan, name, self._warned))
            if self.fleet is not None:
                self.inputs += [WorldInputs(self, FleetMember(self.fleet, name), RELIABLE_10, f"{name}/",
                                            ROBOT_TOPICS),
                                FaultInputs(self, sim, RELIABLE_10, f"{name}/")]
        if self.fleet is None:
            self.inputs += [WorldInputs(self, self.sim, RELIABLE_10),
                            FaultInputs(self, self.sim, RELIABLE_10)]
        else:   # dropped obstacles belong to the world every robot shares
            self.inputs.append(WorldInputs(self, FleetMember(self.fleet, self.sim.name), RELIABLE_10,
                                           topics=(SPAWN_OBSTACLE_TOPIC,)))
        self.create_service(Empty, RESET_SERVICE, self._on_reset)
        self.create_service(SetBool, PAUSE_SERVICE, self._on_pause)

    def _log_start(self, world: World) -> None:
        cfg, sim = self.config, self.sim
        rtf = cfg.node.real_time_factor
        if self.fleet is None:
            who = (f"robot {self.robot.name}, spawn ({cfg.sim.initial_pose.x}, {cfg.sim.initial_pose.y}, "
                   f"{cfg.sim.initial_pose.yaw})")
        else:
            who = "fleet " + ", ".join(
                f"{name} ({robot.robot.name} at {robot.pose.x:g}, {robot.pose.y:g}, {robot.pose.yaw:g})"
                for name, robot in self.fleet.robots.items())
        self.get_logger().info(
            f"sim2d: world {world.name} ({world.source}), {who}, "
            f"real-time factor {'max' if rtf == 0 else rtf}, step {cfg.sim.physics_step} s; charging "
            + (f"on the docks {', '.join(dock.id for dock in world.docks) or '(none in this world)'}"
               if sim.battery.uses_docks else f"within {cfg.battery.station_radius} m of the station"))

    # ------------------------------------------------------------------ stepping
    def _tick(self) -> None:
        """Step as far as the real-time factor, the lockstep gate and one wall budget allow."""
        if self.paused:
            return
        started = time.monotonic()
        sim = self.world_sim
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
        if target - self.world_sim.time_ns > MAX_LAG * 1e9:     # fell behind: drop the debt, report lower RTF
            target = self.world_sim.time_ns + int(MAX_LAG * 1e9)
            self._anchor = (wall_now, target)
        return target

    def _step(self) -> None:
        now = self.world_sim.time_ns
        for outputs in self.outputs:    # stamped commands whose time has come
            outputs.apply_due_commands(now)
        self.world_sim.step()
        self._publish_due()

    def _publish_clock(self, now_ns: int) -> None:
        self.pub_clock.publish(messages.clock(now_ns))
        self._clock_sent = (now_ns, time.monotonic())

    def _publish_due(self) -> None:
        now = self.world_sim.time_ns
        for outputs in self.outputs:
            outputs.publish_due(now)
        # /clock last: a participant that takes /clock t off its queue has every message stamped up
        # to t queued before it, so its timers due at t see the same data on every run.
        if now >= self._clock_due:
            self._publish_clock(now)
            self._clock_due = next_due(self._clock_due, self._clock_period, now)

    def _report_rtf(self) -> None:
        wall_now = time.monotonic()
        wall0, sim0 = self._rtf_window
        now_ns = self.world_sim.time_ns
        achieved = (now_ns - sim0) * 1e-9 / max(wall_now - wall0, 1e-9)
        self._rtf_window = (wall_now, now_ns)
        self.pub_rtf.publish(Float64(data=achieved))
        if wall_now - self._last_log >= self.config.node.rtf_log_period:
            self._last_log = wall_now
            target = self.config.node.real_time_factor
            self.get_logger().info(f"sim2d: real-time factor {achieved:.1f} (target "
                                   f"{'max' if target == 0 else target}), "
                                   f"sim time {self.world_sim.time:.1f} s")

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
        if self._clock_sent[0] < self.world_sim.time_ns:
            self._publish_clock(self.world_sim.time_ns)

    def _unblock_if_free(self, wall_now: float) -> None:
        """Step on at once if the limit has moved past the next step.

        The stepping timer is reset only when one burst does not reach the limit again: resetting it
        on every report (thousands per second) keeps the EventsExecutor's timer manager re-arming
        and starves the other timers (the watchdog, the real-time factor) for seconds.
        """
        limit = self._lockstep_limit(wall_now)
        if limit is not None and self.world_sim.time_ns + self.world_sim.step_ns > limit:
            return
        self._blocked = False
        self._anchor = (wall_now, self.world_sim.time_ns)   # the waiting is not a debt to catch up
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
            self.get_logger().info(f"lockstep: {msg.frame_id} joined at sim time {self.world_sim.time:.3f} s")
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
            self._publish_clock(self.world_sim.time_ns)

    # ------------------------------------------------------------------ inputs
    def _check_cmd_vel_types(self) -> None:
        """Warn once per publisher whose cmd_vel type is not the one a robot subscribes to."""
        for outputs in self.outputs:
            outputs.check_cmd_vel_types()

    def _on_reset(self, request: Empty.Request, response: Empty.Response) -> Empty.Response:
        self.world_sim.reset()
        for outputs in self.outputs:
            outputs.reset()
        self.get_logger().info("sim2d: reset to the spawn pose" + ("s" if self.fleet is not None else ""))
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
            self._anchor = (wall_now, self.world_sim.time_ns)   # resume without catching up
            if self._blocked:
                self._unblock_if_free(wall_now)
        response.success = True
        response.message = "paused" if self.paused else "running"
        return response
