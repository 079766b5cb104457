"""A Nav2 client works unchanged: the calls nav2_simple_commander's BasicNavigator makes (Jazzy),
over the same interfaces, against the stack started by nav-bringup.

BasicNavigator is not on pip (and its source may not be copied here), so ``MiniNavigator`` repeats
its protocol (dockRobotByID and undockRobot included): waitUntilNav2Active polls
``amcl/get_state`` until "active", publishes /initialpose until /amcl_pose arrives, then polls
``bt_navigator/get_state``; tasks are judged by GoalStatus only, as BasicNavigator does.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from lifecycle_msgs.srv import GetState
from nav2_msgs.action import (
    BackUp,
    ComputePathToPose,
    DockRobot,
    FollowWaypoints,
    NavigateThroughPoses,
    NavigateToPose,
    Spin,
    UndockRobot,
)
from nav2_msgs.srv import ClearEntireCostmap, GetCostmap, LoadMap
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from navsuite_testing.ros import REPO, BackgroundSpin
from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.requests import call_until_answered, poll
from ros_tools.tf.ros import TransformListener
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait

pytestmark = [pytest.mark.ros, pytest.mark.slow]
AMCL_POSE_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _pose(x: float, y: float, yaw: float = 0.0) -> PoseStamped:
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return pose


class MiniNavigator:
    """The subset of BasicNavigator's protocol, with its action/service names."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.clients = {name: ActionClient(node, kind, name) for name, kind in (
            ("navigate_to_pose", NavigateToPose), ("navigate_through_poses", NavigateThroughPoses),
            ("follow_waypoints", FollowWaypoints), ("compute_path_to_pose", ComputePathToPose),
            ("spin", Spin), ("backup", BackUp), ("dock_robot", DockRobot), ("undock_robot", UndockRobot))}
        self.initial_pose_pub = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
        self.amcl_poses: list[Any] = []
        node.create_subscription(PoseWithCovarianceStamped, "amcl_pose", self.amcl_poses.append,
                                 AMCL_POSE_QOS)
        self.handle: Any = None
        self.tf = TransformListener(node)
        self._services: dict[str, Any] = {}

    def call(self, srv_type: Any, name: str, request: Any, timeout: float = 30.0) -> Any:
        """Call ``name``, asking again while unanswered (ros_tools.runtime.requests; ``timeout`` s in all).

        Not in BasicNavigator, which waits forever: the server's response can be lost while its
        writer still matches this client's reader (seen in CI: get_state unanswered for 30 s). The
        client is kept per service, so later calls need no new discovery.
        """
        client = self._services.get(name)
        if client is None:
            client = self._services[name] = self.node.create_client(srv_type, name)
        wait(client.service_is_ready, timeout, f"service {name}")
        return call_until_answered(client, request, timeout)

    def _wait_active(self, node_name: str) -> None:
        def active() -> bool:
            state = self.call(GetState, f"{node_name}/get_state", GetState.Request()).current_state
            return state.label == "active"
        wait(active, 120.0, f"{node_name} to be active")

    def wait_until_nav2_active(self) -> None:
        self._wait_active("amcl")
        self.amcl_poses.clear()
        deadline = time.monotonic() + 60.0
        while not self.amcl_poses:
            assert time.monotonic() < deadline, "no /amcl_pose after publishing /initialpose"
            self.set_initial_pose(-2.0, -0.5)
            poll(lambda: bool(self.amcl_poses), 1.0)  # published again each second until AMCL answers
        self._wait_active("bt_navigator")
        # Not in BasicNavigator: AMCL's map -> odom reaches each process a while after /amcl_pose (up
        # to a second under a loaded full-suite run), and until then the planner answers 207 (its
        # costmap has no robot pose) and the controller 102. Seeing it here means it is on the way.
        self.tf.wait_for("map", "base_link", timeout=30.0)

    def set_initial_pose(self, x: float, y: float) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = "map"
        msg.pose.pose = _pose(x, y).pose
        self.initial_pose_pub.publish(msg)

    def start(self, name: str, goal: Any) -> None:
        client = self.clients[name]
        wait(client.server_is_ready, 30.0, f"action {name}")
        future = client.send_goal_async(goal)
        wait(future.done, 30.0, f"{name} acknowledgement")
        self.handle = future.result()
        assert self.handle.accepted, f"{name} rejected the goal"

    def result(self, timeout: float = 300.0) -> Any:
        future = self.handle.get_result_async()
        wait(future.done, timeout, "the task result")
        return future.result()

    def cancel_task(self) -> None:
        future = self.handle.cancel_goal_async()
        wait(future.done, 30.0, "the cancel response")


@pytest.fixture(scope="module", params=["one-process", "isolated"])
def stack(request: Any) -> Iterator[Bringup]:
    """The stack in both layouts: one nav2 process (the default) and ``--isolated``, with
    turtlebot3_world's dock database (docs/docking.md), so docking_server runs too."""
    layout = ["--isolated"] if request.param == "isolated" else []
    bringup = Bringup("--no-initial-pose", *layout, "--params", str(REPO / "config" / "nav2_params.yaml"),
                      "--params", str(REPO / "config" / "docks" / "turtlebot3_world.yaml"))
    try:
        bringup.wait_for_line(READY, timeout=240.0)
        yield bringup
    finally:
        bringup.stop()


@pytest.fixture
def nav(stack, ros_context) -> Iterator[MiniNavigator]:
    node = Node("basic_navigator", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    spin = BackgroundSpin(executor)
    try:
        yield MiniNavigator(node)
    finally:
        print(stack.output(200))  # shown by pytest when the test fails
        spin.stop(node)


def test_basic_navigator_session(nav):
    nav.wait_until_nav2_active()

    nav.start("compute_path_to_pose", ComputePathToPose.Goal(goal=_pose(0.55, 0.0), use_start=False))
    planned = nav.result().result
    path = planned.path
    assert len(path.poses) > 10 and path.header.frame_id == "map", (planned.error_code, planned.error_msg)

    nav.start("navigate_to_pose", NavigateToPose.Goal(pose=_pose(-0.55, -1.65)))
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED

    nav.start("spin", Spin.Goal(target_yaw=1.57, time_allowance=Duration(sec=10)))  # spin() defaults
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED
    backup = BackUp.Goal(speed=0.1, time_allowance=Duration(sec=10))  # backup(0.15, 0.1, 10) defaults
    backup.target.x = 0.15
    nav.start("backup", backup)
    assert nav.result().status in (GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_ABORTED)

    through = NavigateThroughPoses.Goal(poses=[_pose(0.55, -1.65), _pose(0.55, 0.0, 1.57)])
    nav.start("navigate_through_poses", through)
    assert nav.result().status == GoalStatus.STATUS_SUCCEEDED

    nav.start("follow_waypoints", FollowWaypoints.Goal(poses=[_pose(0.55, 1.0), _pose(-0.55, 1.65)]))
    result = nav.result()
    assert result.status == GoalStatus.STATUS_SUCCEEDED and not result.result.missed_waypoints

    nav.start("navigate_to_pose", NavigateToPose.Goal(pose=_pose(-2.0, -0.5)))
    wait(lambda: nav.handle.status == GoalStatus.STATUS_EXECUTING, 30.0, "the navigation to run")
    nav.cancel_task()
    assert nav.result().status == GoalStatus.STATUS_CANCELED

    for costmap in ("global_costmap", "local_costmap"):  # clearAllCostmaps
        nav.call(ClearEntireCostmap, f"{costmap}/clear_entirely_{costmap}", ClearEntireCostmap.Request())
    costmap = nav.call(GetCostmap, "global_costmap/get_costmap", GetCostmap.Request()).map  # getGlobalCostmap
    size = costmap.metadata.size_x * costmap.metadata.size_y
    assert size > 0 and len(costmap.data) == size

    # dockRobotByID(dock_id, nav_to_dock=True), then undockRobot(dock_type=''): the server knows the type
    nav.start("dock_robot", DockRobot.Goal(use_dock_id=True, dock_id="home_dock",
                                           navigate_to_staging_pose=True))
    docked = nav.result()
    assert docked.status == GoalStatus.STATUS_SUCCEEDED, (docked.result.error_code, docked.result.error_msg)
    nav.start("undock_robot", UndockRobot.Goal(dock_type=""))
    undone = nav.result()
    assert undone.status == GoalStatus.STATUS_SUCCEEDED, (undone.result.error_code, undone.result.error_msg)

    url = f"file://{REPO / 'maps' / 'turtlebot3_world.yaml'}"
    response = nav.call(LoadMap, "map_server/load_map", LoadMap.Request(map_url=url))  # changeMap
    assert response.result == LoadMap.Response.RESULT_SUCCESS
