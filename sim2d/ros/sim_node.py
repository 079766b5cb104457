"""The sim2d node: steps the core simulator against a wall-clock timer and publishes in sim time.

Scheduling: a steady (wall) timer runs as many physics steps as ``real_time_factor`` demands (or,
with 0, as many as fit in a short wall budget); after each step the node publishes whatever is due
in sim time: /clock at ``clock_rate``, /odom + /tf + ground_truth at ``odometry.rate``, /scan at
``lidar.rate``, /battery_state at ``battery_rate``. Every stamp is sim time; /clock is the source.

ROS surface (names relative to the node namespace unless absolute):
  sub  cmd_vel (geometry_msgs/Twist, or TwistStamped with enable_stamped_cmd_vel)
  sub  sim2d/teleport (geometry_msgs/PoseStamped, frame map): move the robot, odometry unaware
  pub  /clock, scan (reliable), odom, /tf, /tf_static (transient local), ground_truth (frame map),
       battery_state, sim2d/collisions (PointStamped per new contact),
       sim2d/collision_count (UInt32, transient local), sim2d/real_time_factor (Float64, achieved)
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
from std_msgs.msg import Float64, UInt32
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage

from sim2d.core.robot import Pose2D, robot_model
from sim2d.core.simulator import Simulator
from sim2d.core.world import load_world
from sim2d.ros import messages
from sim2d.ros.config import NODE_NAME, SimConfig, build_config, coerce, defaults

CLOCK_TOPIC, TF_TOPIC, TF_STATIC_TOPIC = "/clock", "/tf", "/tf_static"
SCAN_TOPIC, ODOM_TOPIC, CMD_VEL_TOPIC = "scan", "odom", "cmd_vel"
GROUND_TRUTH_TOPIC, BATTERY_TOPIC = "ground_truth", "battery_state"
COLLISIONS_TOPIC, COLLISION_COUNT_TOPIC = "sim2d/collisions", "sim2d/collision_count"
RTF_TOPIC, TELEPORT_TOPIC = "sim2d/real_time_factor", "sim2d/teleport"
RESET_SERVICE, PAUSE_SERVICE = "sim2d/reset", "sim2d/pause"

TICK_PERIOD = 0.005        # wall seconds between stepping bursts
MAX_MODE_BUDGET = 0.02     # wall seconds of stepping per burst in max mode
MAX_LAG = 0.25             # sim seconds of backlog dropped rather than caught up in a burst

RELIABLE_10 = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _period_ns(rate: float) -> int:
    return max(1, round(1e9 / rate))


class Sim2dNode(Node):
    """One simulated TurtleBot3 on the ROS graph."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)  # type: ignore[arg-type]
        dynamic = ParameterDescriptor(dynamic_typing=True)
        values = {name: coerce(name, self.declare_parameter(name, default, dynamic).value)
                  for name, default in defaults().items()}
        self.config: SimConfig = build_config(values)
        cfg = self.config
        self.robot = robot_model(cfg.node.robot)
        world = load_world(cfg.node.world)
        self.sim = Simulator(world, self.robot, cfg.sim, np.random.default_rng(cfg.node.seed),
                             cfg.lidar, cfg.odometry, cfg.battery, cfg.collision)
        self.paused = False
        self.achieved_rtf = 0.0
        self._warned: set[tuple[str, str]] = set()
        self._make_interfaces()
        self._periods = {"clock": _period_ns(cfg.node.clock_rate), "odom": _period_ns(cfg.odometry.rate),
                         "scan": _period_ns(cfg.lidar.rate), "battery": _period_ns(cfg.node.battery_rate)}
        self._due = dict.fromkeys(self._periods, 0)
        self._publish_due()
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._battery_was_empty = False
        self._anchor = (time.monotonic(), self.sim.time_ns)
        self._rtf_window = (time.monotonic(), self.sim.time_ns)
        self._last_log = time.monotonic()
        self.create_timer(TICK_PERIOD if cfg.node.real_time_factor > 0 else 0.0, self._tick, clock=wall)
        self.create_timer(1.0, self._report_rtf, clock=wall)
        self.create_timer(2.0, self._check_cmd_vel_types, clock=wall)
        rtf = cfg.node.real_time_factor
        self.get_logger().info(
            f"sim2d: world {world.name} ({world.source}), robot {self.robot.name}, spawn "
            f"({cfg.sim.initial_pose.x}, {cfg.sim.initial_pose.y}, {cfg.sim.initial_pose.yaw}), "
            f"real-time factor {'max' if rtf == 0 else rtf}, step {cfg.sim.physics_step} s")

    def _make_interfaces(self) -> None:
        cfg = self.config
        self.pub_clock = self.create_publisher(ClockMsg, CLOCK_TOPIC, RELIABLE_10)
        self.pub_scan = self.create_publisher(LaserScan, SCAN_TOPIC, RELIABLE_10)
        self.pub_odom = self.create_publisher(Odometry, ODOM_TOPIC, RELIABLE_10)
        self.pub_truth = self.create_publisher(Odometry, GROUND_TRUTH_TOPIC, RELIABLE_10)
        self.pub_tf = self.create_publisher(TFMessage, TF_TOPIC, QoSProfile(depth=100))
        self.pub_tf_static = self.create_publisher(TFMessage, TF_STATIC_TOPIC, LATCHED)
        self.pub_battery = self.create_publisher(BatteryState, BATTERY_TOPIC, RELIABLE_10)
        self.pub_collision = self.create_publisher(PointStamped, COLLISIONS_TOPIC, RELIABLE_10)
        self.pub_collision_count = self.create_publisher(UInt32, COLLISION_COUNT_TOPIC, LATCHED)
        self.pub_rtf = self.create_publisher(Float64, RTF_TOPIC, RELIABLE_10)
        self._cmd_type = TwistStamped if cfg.node.enable_stamped_cmd_vel else Twist
        self.create_subscription(self._cmd_type, CMD_VEL_TOPIC, self._on_cmd_vel, RELIABLE_10)
        self.create_subscription(PoseStamped, TELEPORT_TOPIC, self._on_teleport, RELIABLE_10)
        self.create_service(Empty, RESET_SERVICE, self._on_reset)
        self.create_service(SetBool, PAUSE_SERVICE, self._on_pause)
        self._odom = messages.OdometryBuilder(messages.ODOM_FRAME)
        self._truth = messages.OdometryBuilder(messages.MAP_FRAME)
        self._tf = messages.TfBuilder()
        self._scan = messages.ScanBuilder(cfg.lidar)
        self.pub_tf_static.publish(messages.static_transforms(self.robot, 0))
        self.pub_collision_count.publish(UInt32(data=0))

    # ------------------------------------------------------------------ stepping
    def _tick(self) -> None:
        if self.paused:
            return
        started = time.monotonic()
        rtf = self.config.node.real_time_factor
        sim = self.sim
        if rtf > 0:
            wall0, sim0 = self._anchor
            target = sim0 + int((started - wall0) * rtf * 1e9)
            if target - sim.time_ns > MAX_LAG * 1e9:     # fell behind: drop the debt, report lower RTF
                target = sim.time_ns + int(MAX_LAG * 1e9)
                self._anchor = (started, target)
            while sim.time_ns + sim.step_ns <= target:
                self._step()
                if time.monotonic() - started > MAX_MODE_BUDGET:
                    break
        else:
            while time.monotonic() - started < MAX_MODE_BUDGET:
                for _ in range(10):
                    self._step()

    def _step(self) -> None:
        self.sim.step()
        self._publish_due()

    def _publish_due(self) -> None:
        now, due, sim = self.sim.time_ns, self._due, self.sim
        if now >= due["clock"]:
            self.pub_clock.publish(messages.clock(now))
            due["clock"] = self._next_due(due["clock"], self._periods["clock"], now)
        if now >= due["odom"]:
            odom = sim.odometry
            self.pub_odom.publish(self._odom.build(now, odom.pose, sim.v, sim.w, odom.variance_trans,
                                                   odom.variance_rot))
            self.pub_tf.publish(self._tf.build(now, odom.pose))
            self.pub_truth.publish(self._truth.build(now, sim.pose, sim.v, sim.w, 0.0, 0.0))
            due["odom"] = self._next_due(due["odom"], self._periods["odom"], now)
        if now >= due["scan"]:
            self.pub_scan.publish(self._scan.build(now, sim.scan()))
            due["scan"] = self._next_due(due["scan"], self._periods["scan"], now)
        if now >= due["battery"]:
            self.pub_battery.publish(messages.battery_state(now, sim.battery))
            due["battery"] = self._next_due(due["battery"], self._periods["battery"], now)
            self._warn_if_battery_empty(sim.battery.empty)
        if sim.collision_events:
            for event in sim.pop_collision_events():
                self.pub_collision.publish(messages.collision_point(event.time_ns, event.x, event.y))
            self.pub_collision_count.publish(UInt32(data=sim.collision_count))

    def _warn_if_battery_empty(self, empty: bool) -> None:
        """Say once why the robot stopped obeying cmd_vel; say again after a recharge empties it again."""
        if empty and not self._battery_was_empty:
            p = self.sim.battery.params
            self.get_logger().warn(
                f"battery empty at sim time {self.sim.time:.1f} s: the robot ignores cmd_vel until it is "
                f"recharged within {p.station_radius} m of the station ({p.station_x}, {p.station_y}); "
                "set battery.drain_per_meter and battery.drain_per_second to 0 to drive forever")
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

    # ------------------------------------------------------------------ inputs
    def _on_cmd_vel(self, msg: Twist | TwistStamped) -> None:
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        self.sim.command(twist.linear.x, twist.angular.z)

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

    def _on_teleport(self, msg: PoseStamped) -> None:
        if msg.header.frame_id not in ("", messages.MAP_FRAME):
            self.get_logger().warning(f"sim2d: teleport ignored: frame {msg.header.frame_id!r} is not 'map'")
            return
        q = msg.pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        pose = Pose2D(msg.pose.position.x, msg.pose.position.y, yaw)
        if not self.sim.teleport(pose):
            self.get_logger().warning(f"sim2d: teleport to {pose} refused: footprint overlaps an obstacle")

    def _on_reset(self, request: Empty.Request, response: Empty.Response) -> Empty.Response:
        self.sim.reset()
        self.pub_collision_count.publish(UInt32(data=0))
        self.get_logger().info("sim2d: reset to the spawn pose")
        return response

    def _on_pause(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        self.paused = bool(request.data)
        if not self.paused:
            self._anchor = (time.monotonic(), self.sim.time_ns)   # resume without catching up
        response.success = True
        response.message = "paused" if self.paused else "running"
        return response
