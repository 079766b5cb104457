"""sim2d's node with a fleet over rclpy: namespaced topics and TF per robot, robots in each other's
lidar, cmd_vel per robot, robot-robot collisions on both robots, lockstep roles with '/' (issue 48).

The world is the empty 20 m room; the two robots stand in its centre, 1.2 m apart, facing each other:
robot1 a waffle (LDS-01, 3.5 m: the walls, 9 m and more away, are out of its range) and robot2 a tb4
(RPLIDAR A1, 12 m, lidar turned +pi/2 on its mount), so each one's only near return ahead is the other.
"""

from __future__ import annotations

import contextlib
import math
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

from geometry_msgs.msg import PointStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Header, UInt32
from tf2_msgs.msg import TFMessage

from navsuite_testing.ros import spin_until
from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC
from sim2d.core.robot import robot_model
from sim2d.ros.sim_node import Sim2dNode

pytestmark = pytest.mark.ros

S = 1_000_000_000
FLEET = ["robot1:waffle:-0.6,0.0,0.0", f"robot2:tb4:0.6,0.0,{math.pi}"]
MODELS = {"robot1": "waffle", "robot2": "tb4"}
DEEP = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
PER_ROBOT: dict[str, tuple[type, QoSProfile]] = {
    "scan": (LaserScan, DEEP), "odom": (Odometry, DEEP), "ground_truth": (Odometry, DEEP),
    "tf": (TFMessage, DEEP), "tf_static": (TFMessage, LATCHED), "sim2d/collisions": (PointStamped, DEEP),
    "sim2d/collision_count": (UInt32, LATCHED),
}


@dataclass
class FleetRig:
    """The fleet sim node and a probe recording every robot's topics (``/<robot>/<topic>``)."""

    sim: Sim2dNode
    probe: Node
    executor: SingleThreadedExecutor
    received: dict[str, list[Any]] = field(default_factory=lambda: defaultdict(list))

    def spin_until(self, predicate: Any, what: str, timeout: float = 20.0) -> None:
        spin_until(self.executor, predicate, timeout, what)

    def last(self, topic: str) -> Any:
        return self.received[topic][-1]

    def truth(self, robot: str) -> tuple[float, float]:
        position = self.last(f"/{robot}/ground_truth").pose.pose.position
        return position.x, position.y


def _fleet_rig(ros_context: Any, **params: Any) -> Iterator[FleetRig]:
    params = {"world": "empty", "fleet": FLEET, "real_time_factor": 5.0, **params}
    sim = Sim2dNode(context=ros_context,
                    parameter_overrides=[Parameter(name, value=value) for name, value in params.items()])
    probe = Node("fleet_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    rig = FleetRig(sim, probe, executor)
    for robot in MODELS:
        for topic, (msg_type, qos) in PER_ROBOT.items():
            name = f"/{robot}/{topic}"
            probe.create_subscription(msg_type, name, rig.received[name].append, qos)
    probe.create_subscription(Clock, "/clock", rig.received["/clock"].append, DEEP)
    executor.add_node(sim)
    executor.add_node(probe)
    try:
        yield rig
    finally:
        executor.shutdown()
        probe.destroy_node()
        sim.destroy_node()


@pytest.fixture
def rig(ros_context: Any) -> Iterator[FleetRig]:
    yield from _fleet_rig(ros_context)


def _sim_time(stamp: Any) -> float:
    return float(stamp.sec + stamp.nanosec * 1e-9)


def _range_ahead(scan: LaserScan, scan_yaw: float) -> float:
    """The nearest return (m) within 5 degrees of the robot's heading (the scan frame is turned
    ``scan_yaw`` from base_link)."""
    nearest = math.inf
    for i, r in enumerate(scan.ranges):
        bearing = scan.angle_min + i * scan.angle_increment + scan_yaw
        if abs(math.remainder(bearing, 2.0 * math.pi)) <= math.radians(5.0):
            nearest = min(nearest, r)
    return nearest


def _drive(rig: FleetRig, commands: dict[str, float], until: Any, what: str) -> None:
    """Publish ``commands`` (robot -> m/s ahead) on each robot's cmd_vel until ``until()`` holds."""
    pubs = {robot: rig.probe.create_publisher(Twist, f"/{robot}/cmd_vel", 10) for robot in commands}

    def done() -> bool:
        for robot, pub in pubs.items():
            twist = Twist()
            twist.linear.x = commands[robot]
            pub.publish(twist)          # keeps the 0.5 s watchdog fed
        return until()

    rig.spin_until(done, what)
    for pub in pubs.values():
        rig.probe.destroy_publisher(pub)


def test_each_robot_publishes_its_outputs_and_tf_under_its_namespace(rig: FleetRig) -> None:
    wanted = [f"/{robot}/{topic}" for robot in MODELS for topic in PER_ROBOT if topic != "sim2d/collisions"]
    rig.spin_until(lambda: all(rig.received[t] for t in wanted), "every robot's topics")
    for robot, model_name in MODELS.items():
        model = robot_model(model_name)
        assert rig.last(f"/{robot}/scan").header.frame_id == model.scan_frame
        odom = rig.last(f"/{robot}/odom")
        assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_footprint")
        moving = rig.last(f"/{robot}/tf").transforms
        assert [(t.header.frame_id, t.child_frame_id) for t in moving] == [("odom", "base_footprint")]
        static = {(t.header.frame_id, t.child_frame_id) for t in rig.last(f"/{robot}/tf_static").transforms}
        assert static == {("base_footprint", "base_link"), ("base_link", model.scan_frame)}
    assert rig.truth("robot1") == pytest.approx((-0.6, 0.0))
    assert rig.truth("robot2") == pytest.approx((0.6, 0.0))
    # nothing of a robot's is left on the un-namespaced names a lone robot uses
    for topic in ("/tf", "/tf_static", "/scan", "/odom", "/ground_truth", "/battery_state"):
        assert rig.sim.count_publishers(topic) == 0, topic
    assert rig.sim.count_subscribers("/cmd_vel") == 0
    assert all(rig.sim.count_publishers(f"/{robot}/battery_state") == 1 for robot in MODELS)


def test_each_scan_sees_the_other_robot(rig: FleetRig) -> None:
    rig.spin_until(lambda: all(rig.received[f"/{r}/scan"] for r in MODELS), "both scans")
    waffle, tb4 = robot_model("waffle"), robot_model("tb4")
    # robot1's lidar at x = -0.664, robot2's round body from x = 0.429: 1.09 m; the walls are 9.3 m off
    assert _range_ahead(rig.last("/robot1/scan"), waffle.scan_yaw) == pytest.approx(1.093, abs=0.05)
    # robot2's lidar at x = 0.64, robot1's box to x = -0.531: 1.17 m; the wall behind it is 10.6 m off
    assert _range_ahead(rig.last("/robot2/scan"), tb4.scan_yaw) == pytest.approx(1.171, abs=0.05)


def test_cmd_vel_moves_only_its_robot_and_driving_together_collides_both(rig: FleetRig) -> None:
    rig.spin_until(lambda: all(rig.received[f"/{r}/ground_truth"] for r in MODELS), "ground truth")
    _drive(rig, {"robot2": 0.2}, lambda: rig.truth("robot2")[0] < 0.45, "robot2 driving 15 cm")
    assert rig.truth("robot1") == (-0.6, 0.0)          # untouched: not a step of it moved
    assert rig.last("/robot1/odom").twist.twist.linear.x == 0.0
    assert not rig.received["/robot1/sim2d/collisions"] and not rig.received["/robot2/sim2d/collisions"]

    _drive(rig, {"robot1": 0.26, "robot2": 0.3},
           lambda: all(rig.received[f"/{robot}/sim2d/collisions"] for robot in MODELS),
           "a collision event on both robots")
    for robot in MODELS:
        point = rig.received[f"/{robot}/sim2d/collisions"][0].point
        assert -0.6 < point.x < 0.6 and abs(point.y) < 0.2, (robot, point)   # between the two
        rig.spin_until(lambda r=robot: rig.last(f"/{r}/sim2d/collision_count").data >= 1, f"{robot}'s count")
    # the probe takes each topic's queue in turn: wait for ground truth from after the contact
    hit = max(_sim_time(rig.received[f"/{r}/sim2d/collisions"][0].header.stamp) for r in MODELS)
    rig.spin_until(lambda: all(_sim_time(rig.last(f"/{r}/ground_truth").header.stamp) > hit for r in MODELS),
                   "ground truth after the contact")
    gap = rig.truth("robot2")[0] - rig.truth("robot1")[0]
    assert gap < 0.3       # touching: the waffle's front 0.069 m ahead of base_footprint, tb4 radius 0.171


def test_lockstep_waits_for_every_robots_stack_by_role_with_a_slash(ros_context: Any) -> None:
    lockstep = {"lockstep.enabled": True, "lockstep.participants": ["robot1/nav2", "robot2/nav2"],
                "real_time_factor": 0.0}
    with contextlib.contextmanager(_fleet_rig)(ros_context, **lockstep) as rig:
        progress = rig.probe.create_publisher(Header, PROGRESS_TOPIC, PROGRESS_QOS)
        gate = rig.sim.gate
        assert gate is not None

        def report(role: str, time_ns: int) -> None:
            header = Header(frame_id=f"{role}:1")      # pid 1 is alive: only the test decides silence
            header.stamp.sec, header.stamp.nanosec = divmod(time_ns, S)
            progress.publish(header)

        rig.spin_until(lambda: progress.get_subscription_count() > 0, "the sim's progress subscription")
        report("robot1/nav2", S // 10)
        rig.spin_until(lambda: gate.waiting_for == {"robot2/nav2"}, "robot1/nav2 taken for its role")
        clocks = len(rig.received["/clock"])
        rig.spin_until(lambda: len(rig.received["/clock"]) >= clocks + 3, "repeated /clock while waiting")
        assert rig.sim.world_sim.time_ns == 0          # one stack is not the fleet: no step yet
        report("robot2/nav2", S // 10)
        limit = S // 10 + round(rig.sim.config.lockstep.max_lead * S)
        step = rig.sim.world_sim.step_ns
        rig.spin_until(lambda: rig.sim.world_sim.time_ns >= limit - step, "the fleet stepping to its limit")
        assert not gate.waiting_for and rig.sim.world_sim.time_ns <= limit


@pytest.mark.parametrize(("fleet", "message"), [
    (["robot1:waffle"], "fleet: entry 'robot1:waffle': expected 'name:model:x,y,yaw'"),
    (["robot1:kobuki:0,0"], "fleet: entry 'robot1:kobuki:0,0': robot: unknown model 'kobuki'"),
    (["1robot:waffle:0,0"], "robot name '1robot' is not a valid ROS 2 namespace token"),
    (["a:waffle:0,0", "a:tb4:2,0"], "robot name 'a' is declared twice"),
    (["a:waffle:0,0", "b:tb4:0.2,0"], "fleet: robot 'b': spawn (0.2, 0, 0) overlaps robot 'a'"),
])
def test_a_bad_fleet_fails_at_startup_naming_the_entry(ros_context: Any, fleet: list[str],
                                                       message: str) -> None:
    with pytest.raises(ValueError) as error:
        Sim2dNode(context=ros_context, parameter_overrides=[Parameter("world", value="empty"),
                                                            Parameter("fleet", value=fleet)])
    assert message in str(error.value)
