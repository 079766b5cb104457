"""sim2d node over rclpy: topic types, frames, QoS and sim-time rates; cmd_vel, teleport, reset, pause;
a lidar dropout and a dropped obstacle."""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

import rclpy
from geometry_msgs.msg import PointStamped, PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import BatteryState, LaserScan
from std_msgs.msg import Float64, UInt32
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker

from navsuite_testing.ros import spin_until
from ros_tools.runtime.lockstep import LockstepParticipant
from sim2d.ros.sim_node import Sim2dNode

pytestmark = pytest.mark.ros

DEEP = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
PROBE_ROLE = "rate_probe"
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
TOPICS: dict[str, tuple[type, QoSProfile]] = {
    # /scan reliable and deep too: a best-effort reader (sensor data, depth 5) drops scans when the
    # executor falls behind the sim, and the lidar dropout test then misses the last blank scan
    "/clock": (Clock, DEEP), "/scan": (LaserScan, DEEP), "/odom": (Odometry, DEEP),
    "/ground_truth": (Odometry, DEEP), "/tf": (TFMessage, DEEP), "/tf_static": (TFMessage, LATCHED),
    "/battery_state": (BatteryState, DEEP), "/sim2d/collisions": (PointStamped, DEEP),
    "/sim2d/collision_count": (UInt32, LATCHED),
}


def _sim_time(stamp: Any) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


@dataclass
class Rig:
    """The sim node and a probe node recording every message, spun by one executor."""

    sim: Sim2dNode
    probe: Node
    executor: SingleThreadedExecutor
    received: dict[str, list[Any]] = field(default_factory=lambda: defaultdict(list))

    def spin_until(self, predicate: Any, what: str, timeout: float = 20.0) -> None:
        spin_until(self.executor, predicate, timeout, what)

    def last(self, topic: str) -> Any:
        return self.received[topic][-1]

    def truth(self) -> tuple[float, float, float]:
        pose = self.last("/ground_truth").pose.pose
        return pose.position.x, pose.position.y, 2.0 * math.atan2(pose.orientation.z, pose.orientation.w)

    def sim_now(self) -> float:
        return _sim_time(self.last("/clock").clock)

    def wait_sim(self, seconds: float) -> None:
        self.spin_until(lambda: bool(self.received["/clock"]), "/clock")
        end = self.sim_now() + seconds
        self.spin_until(lambda: self.sim_now() >= end, f"{seconds} s of sim time")

    def teleport(self, target: PoseStamped) -> None:
        """Publish one teleport request once the sim subscribes (queued repeats would undo a reset)."""
        self.send("/sim2d/teleport", target)

    def send(self, topic: str, msg: Any) -> None:
        """Publish ``msg`` once on ``topic``, as soon as the sim subscribes to it."""
        pub = self.probe.create_publisher(type(msg), topic, 10)
        self.spin_until(lambda: pub.get_subscription_count() > 0, f"the {topic} subscription")
        pub.publish(msg)

    def call(self, client: Any, request: Any) -> Any:
        assert client.wait_for_service(timeout_sec=10.0)
        future = client.call_async(request)
        self.spin_until(future.done, f"{client.srv_name} response")
        return future.result()


def _rig(ros_context: Any, **params: Any) -> Iterator[Rig]:
    params = {"real_time_factor": 5.0, **params}
    overrides = [Parameter(name, value=value) for name, value in params.items()]
    sim = Sim2dNode(context=ros_context, parameter_overrides=overrides)
    probe = Node("probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    rig = Rig(sim, probe, executor)
    for topic, (msg_type, qos) in TOPICS.items():
        probe.create_subscription(msg_type, topic, lambda m, t=topic: rig.received[t].append(m), qos)
    executor.add_node(sim)
    executor.add_node(probe)
    try:
        yield rig
    finally:
        executor.shutdown()
        probe.destroy_node()
        sim.destroy_node()


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    yield from _rig(ros_context)


def _drive(rig: Rig, v: float, w: float, until: Any, what: str, stamped: bool = False) -> None:
    pub = rig.probe.create_publisher(TwistStamped if stamped else Twist, "/cmd_vel", 10)
    twist = Twist()
    twist.linear.x, twist.angular.z = v, w
    msg = TwistStamped(twist=twist) if stamped else twist

    def moved() -> bool:
        pub.publish(msg)          # keeps the 0.5 s watchdog fed
        return bool(rig.received["/ground_truth"]) and until()

    rig.spin_until(moved, what)
    rig.probe.destroy_publisher(pub)


def test_topics_have_types_frames_and_qos(rig: Rig) -> None:
    rig.spin_until(lambda: all(rig.received[t] for t in TOPICS if t != "/sim2d/collisions"), "every topic")
    scan = rig.last("/scan")
    assert scan.header.frame_id == "base_scan" and len(scan.ranges) == 360
    assert (scan.range_min, scan.range_max) == pytest.approx((0.12, 3.5))
    odom = rig.last("/odom")
    assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_footprint")
    assert odom.pose.covariance[0] > 0.0
    truth = rig.last("/ground_truth")
    assert (truth.header.frame_id, truth.child_frame_id) == ("map", "base_footprint")
    assert rig.truth() == pytest.approx((-2.0, -0.5, 0.0), abs=1e-9)
    tf = rig.last("/tf").transforms[0]
    assert (tf.header.frame_id, tf.child_frame_id) == ("odom", "base_footprint")
    static = {(t.header.frame_id, t.child_frame_id): t.transform.translation
              for t in rig.last("/tf_static").transforms}
    assert static[("base_footprint", "base_link")].z == pytest.approx(0.010)
    scan_mount = static[("base_link", "base_scan")]
    assert (scan_mount.x, scan_mount.y, scan_mount.z) == pytest.approx((-0.064, 0.0, 0.122))
    assert rig.last("/battery_state").percentage == pytest.approx(1.0, abs=0.01)
    assert rig.last("/sim2d/collision_count").data == 0
    expect = {"/scan": ReliabilityPolicy.RELIABLE, "/clock": ReliabilityPolicy.RELIABLE,
              "/tf_static": DurabilityPolicy.TRANSIENT_LOCAL,
              "/sim2d/collision_count": DurabilityPolicy.TRANSIENT_LOCAL}
    for topic, policy in expect.items():
        (info,) = rig.probe.get_publishers_info_by_topic(topic)
        actual = info.qos_profile.durability if isinstance(policy, DurabilityPolicy) else \
            info.qos_profile.reliability
        assert actual == policy, topic
    types = dict(rig.probe.get_topic_names_and_types())
    assert types["/cmd_vel"] == ["geometry_msgs/msg/Twist"]
    assert types["/sim2d/real_time_factor"] == ["std_msgs/msg/Float64"]


@pytest.fixture
def lockstep_rig(ros_context: Any) -> Iterator[Rig]:
    """The rig with the probe as the sim's only lockstep participant: the sim never runs more than
    ``lockstep.max_lead`` ahead of what the probe has taken, so no reliable writer's history overflows
    however loaded the machine is (at factor 5 on the wall clock a starved probe lost 54 of 200 /clock
    messages in a CI run)."""
    for rig in _rig(ros_context, **{"lockstep.enabled": True, "lockstep.participants": [PROBE_ROLE]}):
        participant = LockstepParticipant(rig.probe, PROBE_ROLE)
        try:
            yield rig
        finally:
            participant.destroy()


def test_rates_in_sim_time(lockstep_rig: Rig) -> None:
    rig = lockstep_rig
    rig.wait_sim(4.0)
    start, end = 1.0, 3.0   # a window well inside what was received

    def count(topic: str, stamp_of: Any) -> int:
        return sum(start <= _sim_time(stamp_of(m)) < end for m in rig.received[topic])

    # distinct times: a sim held by lockstep re-sends its current /clock every wall 0.1 s
    clocks = {_sim_time(m.clock) for m in rig.received["/clock"]}
    assert sum(start <= t < end for t in clocks) == pytest.approx(200, abs=1)
    assert count("/odom", lambda m: m.header.stamp) == pytest.approx(60, abs=1)
    assert count("/ground_truth", lambda m: m.header.stamp) == pytest.approx(60, abs=1)
    assert count("/tf", lambda m: m.transforms[0].header.stamp) == pytest.approx(60, abs=1)
    assert count("/scan", lambda m: m.header.stamp) == pytest.approx(10, abs=1)
    assert count("/battery_state", lambda m: m.header.stamp) == pytest.approx(2, abs=1)


def test_cmd_vel_moves_the_ground_truth_as_commanded(rig: Rig) -> None:
    _drive(rig, 0.2, 0.0, lambda: rig.truth()[0] > -1.6, "robot to drive 0.4 m along +x")
    x, y, yaw = rig.truth()
    assert y == pytest.approx(-0.5, abs=1e-6) and yaw == pytest.approx(0.0, abs=1e-6)
    assert rig.last("/ground_truth").twist.twist.linear.x == pytest.approx(0.2)
    # The watchdog: cmd_vel_timeout (0.5 s) after the last command the sim took, the robot brakes at
    # 1 m/s², so it stands 0.7 s of sim time after that command. Counted from the command, not from
    # the end of _drive: commands still queued in DDS reach the sim later on a busy machine.
    rig.spin_until(lambda: rig.last("/ground_truth").twist.twist.linear.x == 0.0, "the robot to stop")
    last_command = rig.sim.sim.command_time_ns * 1e-9
    stopped = min(_sim_time(m.header.stamp) for m in rig.received["/ground_truth"]
                  if _sim_time(m.header.stamp) > last_command and m.twist.twist.linear.x == 0.0)
    slack = 3 * 0.005 + 1.0 / 30.0  # physics steps of rounding, one ground truth period (30 Hz)
    assert 0.5 + 0.2 <= stopped - last_command <= 0.5 + 0.2 + slack
    _drive(rig, 0.0, 1.0, lambda: rig.truth()[2] > 0.5, "robot to turn left")
    assert rig.truth()[0] > x


@pytest.fixture
def stamped_rig(ros_context: Any) -> Iterator[Rig]:
    yield from _rig(ros_context, enable_stamped_cmd_vel=True)


def test_stamped_mode_takes_twist_stamped_and_warns_about_twist(stamped_rig: Rig) -> None:
    rig = stamped_rig
    _drive(rig, 0.2, 0.0, lambda: rig.truth()[0] > -1.8, "TwistStamped to move the robot", stamped=True)
    other = Context()       # DDS refuses two types on one topic within one participant
    rclpy.init(context=other)
    try:
        wrong = Node("twist_talker", context=other)
        wrong.create_publisher(Twist, "/cmd_vel", 10)
        rig.spin_until(lambda: ("/twist_talker", "geometry_msgs/msg/Twist") in rig.sim._warned,
                       "a warning about the Twist publisher")
        wrong.destroy_node()
    finally:
        rclpy.shutdown(context=other)


def test_teleport_moves_truth_not_odometry_and_reset_restores(rig: Rig) -> None:
    rig.spin_until(lambda: bool(rig.received["/odom"]) and bool(rig.received["/ground_truth"]), "odometry")
    target = PoseStamped()
    target.header.frame_id = "map"
    target.pose.position.x, target.pose.position.y = 0.55, 0.55
    target.pose.orientation.z, target.pose.orientation.w = math.sin(0.5), math.cos(0.5)

    rig.teleport(target)
    rig.spin_until(lambda: rig.truth() == pytest.approx((0.55, 0.55, 1.0), abs=1e-6), "teleport")
    odom = rig.last("/odom").pose.pose.position
    assert (odom.x, odom.y) == pytest.approx((0.0, 0.0), abs=1e-6)          # wheels did not turn
    rig.call(rig.probe.create_client(Empty, "/sim2d/reset"), Empty.Request())
    rig.spin_until(lambda: rig.truth() == pytest.approx((-2.0, -0.5, 0.0), abs=1e-9), "reset to spawn")


def test_driving_into_a_pillar_publishes_one_collision(rig: Rig) -> None:
    target = PoseStamped()
    target.header.frame_id = "map"
    target.pose.position.x, target.pose.position.y, target.pose.orientation.w = -1.7, -1.1, 1.0
    rig.spin_until(lambda: bool(rig.received["/ground_truth"]), "ground truth")
    rig.teleport(target)
    rig.spin_until(lambda: rig.truth()[:2] == pytest.approx((-1.7, -1.1)), "teleport in front of the pillar")
    # The count and the contact point travel on two topics: wait until both have arrived.
    _drive(rig, 0.26, 0.0,
           lambda: bool(rig.received["/sim2d/collisions"]) and rig.last("/sim2d/collision_count").data >= 1,
           "a collision (count and contact point)")
    point = rig.last("/sim2d/collisions")
    assert point.header.frame_id == "map"
    assert (point.point.x, point.point.y) == pytest.approx((-1.25, -1.1), abs=0.01)
    assert rig.last("/sim2d/collision_count").data == 1


def test_pause_stops_the_clock_and_resume_restarts_it(rig: Rig) -> None:
    pause = rig.probe.create_client(SetBool, "/sim2d/pause")
    rig.wait_sim(0.2)
    assert rig.call(pause, SetBool.Request(data=True)).success
    frozen = rig.sim.sim.time_ns
    for _ in range(20):
        rig.executor.spin_once(timeout_sec=0.01)
    assert rig.sim.sim.time_ns == frozen
    rig.call(pause, SetBool.Request(data=False))
    rig.spin_until(lambda: rig.sim.sim.time_ns > frozen, "the clock to run again")


def test_a_lidar_dropout_blanks_every_beam_for_its_sim_time(rig: Rig) -> None:
    rig.wait_sim(0.3)
    rig.send("/sim2d/lidar_dropout", Float64(data=1.0))
    rig.spin_until(lambda: any(all(r == math.inf for r in m.ranges) for m in rig.received["/scan"]),
                   "a scan with no return")
    first_blank = next(i for i, m in enumerate(rig.received["/scan"]) if all(r == math.inf for r in m.ranges))
    rig.spin_until(lambda: any(math.isfinite(r) for r in rig.last("/scan").ranges), "the lidar back")
    blank = [m for m in rig.received["/scan"][first_blank:] if all(r == math.inf for r in m.ranges)]
    span = _sim_time(blank[-1].header.stamp) - _sim_time(blank[0].header.stamp)
    assert 0.79 <= span <= 1.0            # 5 Hz scans within the 1 s dropout: 0.8 s from first to last


def test_a_dropped_cylinder_is_seen_by_the_lidar(rig: Rig) -> None:
    rig.spin_until(lambda: bool(rig.received["/scan"]), "a scan")
    assert rig.last("/scan").ranges[0] > 0.6           # nothing within 0.6 m ahead of the spawn
    marker = Marker(type=Marker.CYLINDER, action=Marker.ADD)
    marker.header.frame_id = "map"
    marker.pose.position.x, marker.pose.position.y = -1.5, -0.5
    marker.scale.x = marker.scale.y = 0.2
    rig.send("/sim2d/spawn_obstacle", marker)
    scan_x = -2.0 + rig.sim.robot.scan_offset[0]        # the spawn faces +x; the lidar sits behind its centre
    rig.spin_until(lambda: rig.last("/scan").ranges[0] == pytest.approx(-1.6 - scan_x, abs=0.05),
                   "the cylinder 0.4 m ahead in the scan")
