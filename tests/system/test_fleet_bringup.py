"""`nav-bringup --robots 2` on turtlebot3_world (issue 48): one namespaced Nav2 stack per robot, as Nav2
Jazzy's cloned multi-robot bringup runs them, and `nav-goal --namespace` driving each robot.

robot1 starts at the world's first spawn (-2.0, -0.5) and robot2 in the pillar grid (-0.55, -0.55), the
world's second spawn. Their goals lie on opposite sides of the world, so the paths never cross; both
goals run at the same time.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from navsuite_testing.ros import spin_until, start_python, stop_process
from tests.helpers.nav_ros_bt_stack import READY, Bringup

pytestmark = [pytest.mark.ros, pytest.mark.slow]

SPAWNS = {"robot1": (-2.0, -0.5), "robot2": (-0.55, -0.55)}
GOALS = {"robot1": (-1.5, 1.5, 0.0), "robot2": (1.6, -0.55, 0.0)}
#: m: the goal checker's xy_goal_tolerance (config/nav2_params.yaml) plus AMCL's error.
REACHED = 0.25 + 0.1
LOCALIZED = 0.25  # m between AMCL's pose and the truth once the initial pose is in


def _xy(msg: Any) -> tuple[float, float]:
    return msg.pose.pose.position.x, msg.pose.pose.position.y


def test_two_namespaced_stacks_localize_and_each_robot_reaches_its_goal(ros_context: Any) -> None:
    import rclpy
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from nav_msgs.msg import Odometry
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import UInt32
    from tf2_msgs.msg import TFMessage

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    stack = Bringup("--robots", "2")
    node = rclpy.create_node("fleet_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    truth: dict[str, Any] = {}
    amcl: dict[str, Any] = {}
    collisions: dict[str, int] = {}
    map_to_odom: set[str] = set()  # TF topics that carried AMCL's map -> odom

    def on_tf(topic: str) -> Any:
        def record(msg: TFMessage) -> None:
            if any(t.header.frame_id == "map" and t.child_frame_id == "odom" for t in msg.transforms):
                map_to_odom.add(topic)
        return record

    def keep(store: dict[str, Any], robot: str, field: str = "") -> Any:
        def record(msg: Any) -> None:
            store[robot] = getattr(msg, field) if field else msg
        return record

    for robot in SPAWNS:
        node.create_subscription(Odometry, f"/{robot}/ground_truth", keep(truth, robot), 10)
        node.create_subscription(PoseWithCovarianceStamped, f"/{robot}/amcl_pose", keep(amcl, robot), latched)
        node.create_subscription(UInt32, f"/{robot}/sim2d/collision_count", keep(collisions, robot, "data"),
                                 latched)
    for topic in ("/tf", "/robot1/tf", "/robot2/tf"):
        node.create_subscription(TFMessage, topic, on_tf(topic), 100)
    goals: list[Any] = []
    try:
        stack.wait_for_line(READY, timeout=180.0)
        # every node of each stack in its robot's namespace; none left in the root namespace
        expected = {(name, f"/{robot}{namespace}") for robot in SPAWNS for name, namespace in (
            ("amcl", ""), ("map_server", ""), ("bt_navigator", ""), ("lifecycle_manager_navigation", ""),
            ("local_costmap", "/local_costmap"), ("global_costmap", "/global_costmap"))}
        spin_until(executor, lambda: expected <= set(node.get_node_names_and_namespaces()), 30.0,
                   f"the nodes {sorted(expected)}")
        graph = node.get_node_names_and_namespaces()
        assert not [(name, ns) for name, ns in graph if name in ("amcl", "controller_server") and ns == "/"]

        # each robot's AMCL localizes it from its own scans, and its TF travels on its own topic
        def localized() -> bool:
            return all(robot in amcl and robot in truth
                       and math.dist(_xy(amcl[robot]), _xy(truth[robot])) < LOCALIZED for robot in SPAWNS)

        spin_until(executor, localized, 60.0, "both robots localized near their spawns")
        spin_until(executor, lambda: {"/robot1/tf", "/robot2/tf"} <= map_to_odom, 30.0,
                   "map -> odom on /robot1/tf and /robot2/tf")
        assert "/tf" not in map_to_odom

        goals = [start_python("nav_stack.ros.goal_cli",
                              ["--namespace", robot, "goto", *map(str, GOALS[robot])]) for robot in SPAWNS]
        spin_until(executor, lambda: all(goal.poll() is not None for goal in goals), 120.0,
                   "both nav-goal runs")
        for robot, goal in zip(SPAWNS, goals, strict=True):
            out = stop_process(goal)
            assert goal.returncode == 0, f"{robot}:\n{out}\n{stack.output()}"
            assert f"/{robot}/navigate_to_pose" in out and "result: SUCCEEDED (error_code 0)" in out, out
        spin_until(executor, lambda: all(robot in collisions for robot in SPAWNS), 10.0, "collision counts")
        for robot, (x, y, _) in GOALS.items():
            assert math.dist(_xy(truth[robot]), (x, y)) < REACHED, (robot, _xy(truth[robot]))
            assert collisions[robot] == 0, (robot, collisions)
    finally:
        for goal in goals:
            stop_process(goal)
        node.destroy_node()
        executor.shutdown()
        assert stack.stop() is not None
