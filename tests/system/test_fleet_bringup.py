"""`nav-bringup --robots 2` on turtlebot3_world (issue 48): one namespaced Nav2 stack per robot, as Nav2
Jazzy's cloned multi-robot bringup runs them; robot1 follows `nav-goal --namespace robot1` while a
BasicNavigator in robot2's namespace (tests/helpers/mini_navigator.py) drives robot2.

robot1 starts at the world's first spawn (-2.0, -0.5) and robot2 in the pillar grid (-0.55, -0.55), the
world's second spawn. Their goals lie on opposite sides of the world, so the paths never cross; both
navigations run at the same time.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from navsuite_testing.ros import BackgroundSpin, start_python, stop_process
from tests.helpers.mini_navigator import MiniNavigator, TaskResult, pose_stamped
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait

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
    from action_msgs.msg import GoalStatus, GoalStatusArray
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from nav_msgs.msg import Odometry
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_action_status_default
    from std_msgs.msg import UInt32
    from tf2_msgs.msg import TFMessage

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    stack = Bringup("--robots", "2")
    node = rclpy.create_node("fleet_probe", context=ros_context)
    navigator = MiniNavigator(ros_context, namespace="robot2")  # BasicNavigator(namespace='robot2')
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(navigator.node)
    truth: dict[str, Any] = {}
    amcl: dict[str, Any] = {}
    collisions: dict[str, int] = {}
    map_to_odom: set[str] = set()  # TF topics that carried AMCL's map -> odom
    executing: dict[str, bool] = {}  # robot -> its navigate_to_pose runs a goal now
    overlapped: list[bool] = []  # set once both robots' navigations ran at the same moment

    def on_tf(topic: str) -> Any:
        def record(msg: TFMessage) -> None:
            if any(t.header.frame_id == "map" and t.child_frame_id == "odom" for t in msg.transforms):
                map_to_odom.add(topic)
        return record

    def keep(store: dict[str, Any], robot: str, field: str = "") -> Any:
        def record(msg: Any) -> None:
            store[robot] = getattr(msg, field) if field else msg
        return record

    def on_status(robot: str) -> Any:
        def record(msg: GoalStatusArray) -> None:
            executing[robot] = any(s.status == GoalStatus.STATUS_EXECUTING for s in msg.status_list)
            if all(executing.get(r, False) for r in SPAWNS):
                overlapped.append(True)
        return record

    for robot in SPAWNS:
        node.create_subscription(Odometry, f"/{robot}/ground_truth", keep(truth, robot), 10)
        node.create_subscription(PoseWithCovarianceStamped, f"/{robot}/amcl_pose", keep(amcl, robot), latched)
        node.create_subscription(UInt32, f"/{robot}/sim2d/collision_count", keep(collisions, robot, "data"),
                                 latched)
        node.create_subscription(GoalStatusArray, f"/{robot}/navigate_to_pose/_action/status",
                                 on_status(robot), qos_profile_action_status_default)
    for topic in ("/tf", "/robot1/tf", "/robot2/tf"):
        node.create_subscription(TFMessage, topic, on_tf(topic), 100)
    spin = BackgroundSpin(executor)
    goal: Any = None
    try:
        stack.wait_for_line(READY, timeout=180.0)
        # every node of each stack in its robot's namespace; none left in the root namespace
        expected = {(name, f"/{robot}{namespace}") for robot in SPAWNS for name, namespace in (
            ("amcl", ""), ("map_server", ""), ("bt_navigator", ""), ("lifecycle_manager_navigation", ""),
            ("local_costmap", "/local_costmap"), ("global_costmap", "/global_costmap"))}
        wait(lambda: expected <= set(node.get_node_names_and_namespaces()), 30.0,
             f"the nodes {sorted(expected)}")
        graph = node.get_node_names_and_namespaces()
        assert not [(name, ns) for name, ns in graph if name in ("amcl", "controller_server") and ns == "/"]
        # bonds on each robot's relative `bond`, as Nav2's (no remap): none left on the global /bond
        wait(lambda: all(node.count_publishers(f"/{robot}/bond") > 0 for robot in SPAWNS), 10.0,
             "the bond heartbeats of both stacks")
        assert node.count_publishers("/bond") == 0

        # each robot's AMCL localizes it from its own scans, and its TF travels on its own topic
        def localized() -> bool:
            return all(robot in amcl and robot in truth
                       and math.dist(_xy(amcl[robot]), _xy(truth[robot])) < LOCALIZED for robot in SPAWNS)

        wait(localized, 60.0, "both robots localized near their spawns")
        wait(lambda: {"/robot1/tf", "/robot2/tf"} <= map_to_odom, 30.0,
             "map -> odom on /robot1/tf and /robot2/tf")
        assert "/tf" not in map_to_odom

        # robot1 follows nav-goal's goal; meanwhile robot2's BasicNavigator session, as its users write it
        goal = start_python("nav_stack.ros.tools.goal_cli",
                            ["--namespace", "robot1", "goto", *map(str, GOALS["robot1"])])
        navigator.set_initial_pose(*SPAWNS["robot2"])
        navigator.wait_until_nav2_active()
        wait(lambda: executing.get("robot1", False), 60.0, "robot1's navigate_to_pose to run")
        assert navigator.go_to_pose(pose_stamped(*GOALS["robot2"])), "robot2's navigator rejected the goal"
        wait(lambda: navigator.is_task_complete() and goal.poll() is not None, 120.0, "both navigations")
        response = navigator.result()
        assert navigator.get_result() is TaskResult.SUCCEEDED, (response.status, response.result.error_code,
                                                                response.result.error_msg, stack.output())
        out = stop_process(goal)
        assert goal.returncode == 0, f"robot1:\n{out}\n{stack.output()}"
        assert "/robot1/navigate_to_pose" in out and "result: SUCCEEDED (error_code 0)" in out, out
        assert overlapped, "robot2's navigation never ran while robot1's did"
        wait(lambda: all(robot in collisions for robot in SPAWNS), 10.0, "collision counts")
        for robot, (x, y, _) in GOALS.items():
            assert math.dist(_xy(truth[robot]), (x, y)) < REACHED, (robot, _xy(truth[robot]))
            assert collisions[robot] == 0, (robot, collisions)
    finally:
        if goal is not None:
            stop_process(goal)
        spin.stop(node, navigator.node)
        assert stack.stop() is not None
