"""One robot's ROS surface in sim2d: its sensors, TF, battery and contacts out, cmd_vel in.

Why a helper apart from the node: a fleet (issue 48) gives every robot the same outputs under its
own namespace, and a robot alone is the one-robot case on the un-namespaced topics. The node keeps
what the world has once (/clock, stepping, lockstep, reset, pause) and, after every physics step,
asks each robot's outputs to publish what is due in sim time; /clock goes last (sim_node.py says why).

Names (``prefix`` is "" for a robot alone, ``robot1/`` in a fleet; relative names resolve in the
node's namespace):
  pub  <prefix>scan (reliable), <prefix>odom, <prefix>ground_truth (frame map), <prefix>battery_state,
       <prefix>detected_dock_pose (only in a world with docks), <prefix>sim2d/collisions (PointStamped
       per new contact), <prefix>sim2d/collision_count (UInt32, transient local),
       <prefix>sim2d/clearance (Float64, m, with each odom while someone subscribes)
  pub  TF: /tf and /tf_static for a robot alone; <prefix>tf and <prefix>tf_static in a fleet, as Nav2's
       multi-robot bringup remaps /tf to tf in each robot's namespace. The frame ids stay unprefixed
       (odom, base_footprint, base_link, base_scan...): each robot's tree travels on its own topics.
  sub  <prefix>cmd_vel (Twist, or TwistStamped with enable_stamped_cmd_vel, sim2d/core/command_schedule.py)
"""

from __future__ import annotations

import math
from collections.abc import Callable

from geometry_msgs.msg import PointStamped, PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import BatteryState, LaserScan
from std_msgs.msg import Float64, UInt32
from tf2_msgs.msg import TFMessage

from sim2d.core.clearance import robot_clearance
from sim2d.core.command_schedule import CommandSchedule
from sim2d.core.geometry import FloatArray
from sim2d.core.simulator import RobotSim
from sim2d.ros import messages
from sim2d.ros.config import SimConfig

SCAN_TOPIC, ODOM_TOPIC, CMD_VEL_TOPIC = "scan", "odom", "cmd_vel"
GROUND_TRUTH_TOPIC, BATTERY_TOPIC = "ground_truth", "battery_state"
COLLISIONS_TOPIC, COLLISION_COUNT_TOPIC = "sim2d/collisions", "sim2d/collision_count"
CLEARANCE_TOPIC = "sim2d/clearance"
DETECTED_DOCK_TOPIC = "detected_dock_pose"   # opennav_docking SimpleChargingDock's subscription

RELIABLE_10 = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def period_ns(rate: float) -> int:
    """The period (ns of sim time) of ``rate`` (Hz)."""
    return max(1, round(1e9 / rate))


def next_due(due: int, period: int, now: int) -> int:
    """Next slot on the fixed grid of ``period`` (ns): the average rate is exact whatever the step."""
    due += period
    return due if due > now else now + period


def tf_topics(name: str) -> tuple[str, str]:
    """The TF topics of robot ``name``: /tf and /tf_static alone (""), ``<name>/tf`` and
    ``<name>/tf_static`` in a fleet (Nav2's multi-robot remapping of /tf to tf)."""
    return (f"{name}/tf", f"{name}/tf_static") if name else ("/tf", "/tf_static")


class RobotOutputs:
    """Publishes one robot's outputs when due and feeds it the commands on its cmd_vel.

    Args:
        node: the sim node that owns the publishers and the subscription.
        sim: the robot.
        config: the node's configuration (rates, stamped cmd_vel).
        scan: takes the robot's scan now (a fleet's includes the other robots).
        name: the robot's name in a fleet, its namespace; "" for a robot alone (un-namespaced topics).
        warned: (publisher node, type) pairs already warned about a wrong cmd_vel type, shared by
            the node's robots so that one wrong publisher is named once.
    """

    def __init__(self, node: Node, sim: RobotSim, config: SimConfig, scan: Callable[[], FloatArray],
                 name: str = "", warned: set[tuple[str, str]] | None = None) -> None:
        self.node, self.sim, self.config, self.name = node, sim, config, name
        self._scan_now = scan
        self.prefix = f"{name}/" if name else ""
        self.label = f"{name}: " if name else ""   # in log lines, after "sim2d: "
        self.warned = warned if warned is not None else set()
        pub, p = node.create_publisher, self.prefix
        tf_topic, tf_static_topic = tf_topics(name)
        self.pub_scan = pub(LaserScan, p + SCAN_TOPIC, RELIABLE_10)
        self.pub_odom = pub(Odometry, p + ODOM_TOPIC, RELIABLE_10)
        self.pub_truth = pub(Odometry, p + GROUND_TRUTH_TOPIC, RELIABLE_10)
        self.pub_tf = pub(TFMessage, tf_topic, QoSProfile(depth=100))
        self.pub_tf_static = pub(TFMessage, tf_static_topic, LATCHED)
        self.pub_battery = pub(BatteryState, p + BATTERY_TOPIC, RELIABLE_10)
        self.pub_collision = pub(PointStamped, p + COLLISIONS_TOPIC, RELIABLE_10)
        self.pub_collision_count = pub(UInt32, p + COLLISION_COUNT_TOPIC, LATCHED)
        self.pub_clearance = pub(Float64, p + CLEARANCE_TOPIC, RELIABLE_10)
        self.pub_dock = pub(PoseStamped, p + DETECTED_DOCK_TOPIC, RELIABLE_10) if sim.docks else None
        self.cmd_type = TwistStamped if config.node.enable_stamped_cmd_vel else Twist
        self.cmd_vel_topic = p + CMD_VEL_TOPIC
        node.create_subscription(self.cmd_type, self.cmd_vel_topic, self._on_cmd_vel, RELIABLE_10)
        self.commands = CommandSchedule(round(config.node.stamped_cmd_vel_delay * 1e9))
        self._late_warned = 0
        self._odom = messages.OdometryBuilder(messages.ODOM_FRAME)
        self._truth = messages.OdometryBuilder(messages.MAP_FRAME)
        self._tf = messages.TfBuilder()
        self._scan = messages.ScanBuilder(sim.lidar.params, sim.robot.scan_frame)
        self._periods = {"odom": period_ns(config.odometry.rate), "scan": period_ns(sim.lidar.params.rate),
                         "battery": period_ns(config.node.battery_rate),
                         "dock": period_ns(config.dock_detection.rate)}
        self._due = dict.fromkeys(self._periods, 0)
        self._battery_was_empty = False  # before the first publish: it warns about a battery empty at start
        self._charging_reported = False  # battery.charging in the newest battery_state
        self.pub_tf_static.publish(messages.static_transforms(sim.robot, 0))
        self.pub_collision_count.publish(UInt32(data=0))

    # ------------------------------------------------------------------ outputs
    def apply_due_commands(self, now_ns: int) -> None:
        """Give the robot the stamped commands whose time has come (before the step at ``now_ns``)."""
        for command in self.commands.due(now_ns):
            self.sim.command(command.v, command.w)

    def publish_due(self, now: int) -> None:
        """Publish whatever is due at sim time ``now`` (ns), each output at its own rate."""
        due, sim, periods = self._due, self.sim, self._periods
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
            # about 20 physics steps (bench/bench_clearance.py). The world's obstacles only, not the
            # fleet's other robots.
            if self.pub_clearance.get_subscription_count() > 0:
                clearance = robot_clearance(sim.robot, sim.pose, sim.lidar.geometry)
                self.pub_clearance.publish(Float64(data=clearance))
            due["odom"] = next_due(due["odom"], periods["odom"], now)
        if now >= due["scan"]:
            ranges = self._scan_now()  # taken even when lost: the lidar's noise stream stays the same
            if not lost(SCAN_TOPIC, now):
                self.pub_scan.publish(self._scan.build(now, ranges))
            due["scan"] = next_due(due["scan"], periods["scan"], now)
        if self.pub_dock is not None and now >= due["dock"]:
            detection = sim.detect_dock()
            if detection is not None:
                self.pub_dock.publish(messages.detected_dock_pose(now, detection))
            due["dock"] = next_due(due["dock"], periods["dock"], now)
        self._publish_battery(now)
        if sim.collision_events:
            for event in sim.pop_collision_events():
                self.pub_collision.publish(messages.collision_point(event.time_ns, event.x, event.y))
                if event.other is not None:
                    self.node.get_logger().info(
                        f"sim2d: {self.name} and {event.other} collided at ({event.x:.3f}, {event.y:.3f}) "
                        f"at sim time {event.time_ns * 1e-9:.3f} s")
            self.pub_collision_count.publish(UInt32(data=sim.collision_count))

    def _publish_battery(self, now: int) -> None:
        """battery_state at its rate, and at once when charging on a dock starts or stops (Nav2's docking
        server waits only ``wait_charge_timeout``, 5 s, for it)."""
        sim, due = self.sim, self._due
        dock_change = sim.battery.uses_docks and sim.battery.charging != self._charging_reported
        if now < due["battery"] and not dock_change:
            return
        if not sim.topic_loss.lost(BATTERY_TOPIC, now):
            self.pub_battery.publish(messages.battery_state(now, sim.battery))
        if dock_change:
            self._log_dock_change()
        self._charging_reported = sim.battery.charging
        if now >= due["battery"]:
            due["battery"] = next_due(due["battery"], self._periods["battery"], now)
        self._warn_if_battery_empty(sim.battery.empty)

    def reset(self) -> None:
        """After the robot went back to its spawn: forget queued commands, publish the zero count."""
        self.commands.clear()
        self.pub_collision_count.publish(UInt32(data=0))

    def _log_dock_change(self) -> None:
        """Say when charging on a dock starts or stops, and where the robot stands against the dock."""
        sim = self.sim
        if sim.battery.charging and sim.docked is not None:
            dock = sim.docked
            offset_mm = 1000.0 * math.hypot(sim.pose.x - dock.pose.x, sim.pose.y - dock.pose.y)
            self.node.get_logger().info(
                f"sim2d: {self.label}charging on {dock.id} at sim time {sim.time:.3f} s (base_link "
                f"{offset_mm:.0f} mm from its contact pose, {sim.battery.current:.1f} A)")
        else:
            self.node.get_logger().info(f"sim2d: {self.label}charging stopped at sim time {sim.time:.3f} s")

    def _warn_if_battery_empty(self, empty: bool) -> None:
        """Say once why the robot stopped obeying cmd_vel; say again after a recharge empties it again."""
        if empty and not self._battery_was_empty:
            battery = self.sim.battery
            p = battery.params
            where = (f"on a dock ({', '.join(dock.id for dock in self.sim.docks) or 'the world has none'})"
                     if battery.uses_docks else
                     f"within {p.station_radius} m of the station ({p.station_x}, {p.station_y})")
            self.node.get_logger().warn(
                f"{self.label}battery empty at sim time {self.sim.time:.1f} s: the robot ignores cmd_vel "
                f"until it is recharged {where}; set battery.drain_per_meter and battery.drain_per_second "
                "to 0 to drive forever")
        self._battery_was_empty = empty

    # ------------------------------------------------------------------ cmd_vel
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
        self.node.get_logger().warning(
            f"sim2d: {self.label}{self.commands.late} stamped cmd_vel arrived after stamp + "
            f"stamped_cmd_vel_delay ({self.config.node.stamped_cmd_vel_delay} s; worst "
            f"{self.commands.worst_late_ns * 1e-9:.3f} s late) and took effect on arrival: runs are not "
            "exact repeats; raise the delay")

    def check_cmd_vel_types(self) -> None:
        """Warn once per publisher whose cmd_vel type is not the one this robot subscribes to."""
        topic = self.node.resolve_topic_name(self.cmd_vel_topic)
        expected = "geometry_msgs/msg/TwistStamped" if self.cmd_type is TwistStamped \
            else "geometry_msgs/msg/Twist"
        for info in self.node.get_publishers_info_by_topic(topic):
            key = (f"{info.node_namespace.rstrip('/')}/{info.node_name}", info.topic_type)
            if info.topic_type != expected and key not in self.warned:
                self.warned.add(key)
                self.node.get_logger().warning(
                    f"sim2d: {key[0]} publishes {info.topic_type} on {topic}, but sim2d expects {expected} "
                    f"(enable_stamped_cmd_vel={self.config.node.enable_stamped_cmd_vel}); "
                    "its commands are ignored")
