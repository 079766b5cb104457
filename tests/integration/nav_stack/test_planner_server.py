"""planner_server on sim2d: paths across turtlebot3_world and every refusal with its Jazzy error code."""

from __future__ import annotations

import math
import subprocess
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import ComputePathThroughPoses, ComputePathToPose
from nav2_msgs.srv import IsPathValid
from nav_msgs.msg import Path
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import String

from nav_stack.core.map_io import load_map
from nav_stack.ros.planning.planner_server import build_nodes
from navsuite_testing.nav.world import (
    LATCHED,
    MAP_YAML,
    Harness,
    WorldNode,
    get_result,
    send_goal,
    server_args,
    start_sim,
    stop_process,
)
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient
from tests.helpers.stalling_planner import StallingPlanner

pytestmark = pytest.mark.ros
Codes = ComputePathToPose.Result


@pytest.fixture(scope="module")
def sim() -> Iterator[subprocess.Popen[str]]:
    proc = start_sim(rtf=3.0)
    try:
        yield proc
    finally:
        stop_process(proc)


@pytest.fixture
def planner(ros_context: Any, sim: subprocess.Popen[str]) -> Iterator[tuple[Node, Any, WorldNode, Any]]:
    """A running planner_server with its costmap, the world, and a probe node with an action client."""
    harness = Harness(ros_context)
    try:
        world = WorldNode(context=ros_context)
        probe = Node("planner_probe", context=ros_context)
        nodes = build_nodes(use_sim_time=True, context=ros_context, cli_args=server_args())
        harness.add(world, probe, *nodes)
        wait_until(lambda: world.truth is not None, 20.0, "sim2d ground truth")
        world.reset_sim()
        harness.bring_up(nodes[0])
        wait_until(nodes[1].ready.done, 40.0, "global costmap never updated")
        yield probe, nodes[0], world, ActionClient(probe, ComputePathToPose, "compute_path_to_pose")
    finally:
        harness.close()


def goal_pose(x: float, y: float, yaw: float = 0.0, frame: str = "map") -> PoseStamped:
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


def plan(client: Any, goal: PoseStamped, planner_id: str = "", timeout: float = 15.0) -> tuple[int, Any]:
    request = ComputePathToPose.Goal(goal=goal, planner_id=planner_id, use_start=False)
    return get_result(send_goal(client, request), timeout)


@pytest.mark.parametrize("planner_id", ["GridBased", "ThetaStar"])
def test_paths_across_the_world_avoid_obstacles(planner: Any, planner_id: str) -> None:
    probe, server, _, client = planner
    plans: list[Path] = []
    probe.create_subscription(Path, "/plan", plans.append, 10)
    costs, spec = server.costmap_node.snapshot()
    for gx, gy in [(2.0, 0.0), (0.0, 2.0)]:
        status, result = plan(client, goal_pose(gx, gy), planner_id)
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        assert result.error_code == Codes.NONE
        xy = np.array([(p.pose.position.x, p.pose.position.y) for p in result.path.poses])
        assert result.path.header.frame_id == "map"
        assert np.hypot(*(xy[0] - (-2.0, -0.5))) < 0.1, "the path must start at the robot (TF)"
        assert np.hypot(*(xy[-1] - (gx, gy))) < 0.1
        length = float(np.hypot(*np.diff(xy, axis=0).T).sum())
        straight = math.hypot(gx + 2.0, gy + 0.5)
        assert straight <= length < 1.5 * straight, f"implausible length {length:.2f} m"
        mx, my = spec.world_to_cell(xy[:, 0], xy[:, 1])
        assert (costs[my, mx] < 253).all(), "a path pose lies on an inscribed or lethal cell"
    wait_until(lambda: len(plans) >= 2, 10.0, "two /plan messages")


def test_refusals_carry_their_error_codes(planner: Any) -> None:
    _, _, _, client = planner
    cases = [
        (goal_pose(0.0, 0.0), "ThetaStar", Codes.GOAL_OCCUPIED),        # the centre pillar
        (goal_pose(10.0, 10.0), "GridBased", Codes.GOAL_OUTSIDE_MAP),
        (goal_pose(1.0, 1.0), "NoSuchPlanner", Codes.INVALID_PLANNER),
        (goal_pose(1.0, 0.5, frame="no_such_frame"), "GridBased", Codes.TF_ERROR),
    ]
    for goal, planner_id, code in cases:
        status, result = plan(client, goal, planner_id)
        assert status == GoalStatus.STATUS_ABORTED
        assert (result.error_code, bool(result.error_msg)) == (code, True), result.error_msg
    nan_goal = goal_pose(1.0, 0.5)
    nan_goal.pose.orientation.w = math.nan
    status, result = plan(client, nan_goal, "GridBased")
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, Codes.UNKNOWN)
    assert "orientation" in result.error_msg


def test_goal_in_another_frame_is_transformed(planner: Any) -> None:
    _, _, _, client = planner
    # odom's origin is the spawn pose (-2.0, -0.5): odom (2.0, 2.5) is map (0.0, 2.0).
    status, result = plan(client, goal_pose(2.0, 2.5, frame="odom"), "GridBased")
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    end = result.path.poses[-1].pose.position
    assert (end.x, end.y) == pytest.approx((0.0, 2.0), abs=0.05)


def test_planner_selector_and_through_poses(planner: Any) -> None:
    probe, server, _, _ = planner
    selector = probe.create_publisher(String, "/planner_selector", LATCHED)
    selector.publish(String(data="NoSuchPlanner"))
    wait_until(lambda: server._selector.selected == "NoSuchPlanner", 10.0, "the selection")
    through = ActionClient(probe, ComputePathThroughPoses, "compute_path_through_poses")
    request = ComputePathThroughPoses.Goal(goals=[goal_pose(0.0, 2.0), goal_pose(2.0, 0.0)], use_start=False)
    status, result = get_result(send_goal(through, request), 15.0)
    assert result.error_code == ComputePathThroughPoses.Result.INVALID_PLANNER, "the selector was ignored"
    selector.publish(String(data="GridBased"))
    wait_until(lambda: server._selector.selected == "GridBased", 10.0, "the selection")
    status, result = get_result(send_goal(through, request), 15.0)
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    xy = np.array([(p.pose.position.x, p.pose.position.y) for p in result.path.poses])
    assert np.hypot(*(xy - (0.0, 2.0)).T).min() < 0.05, "the via point was skipped"
    status, result = get_result(send_goal(through, ComputePathThroughPoses.Goal(goals=[])), 15.0)
    assert result.error_code == ComputePathThroughPoses.Result.NO_VIAPOINTS_GIVEN


def test_a_cancel_stops_a_search_in_progress_and_the_node_keeps_serving(planner: Any) -> None:
    """The search runs on the planner's worker thread: while it runs, the node answers is_path_valid,
    and a cancel stops it (Nav2 Jazzy's cancel_checker) with the goal CANCELED; the next goal is
    planned as usual."""
    probe, server, _, client = planner
    stalling = StallingPlanner()
    server.core.planners["Stalling"] = stalling
    handle = send_goal(client, ComputePathToPose.Goal(goal=goal_pose(2.0, 0.0), planner_id="Stalling"))
    wait_until(stalling.started.is_set, 15.0, "the stalling search to start")
    checker = probe.create_client(IsPathValid, "is_path_valid")
    path = Path()
    path.header.frame_id = "map"
    path.poses = [goal_pose(-1.5, -0.5)]
    answered = checker.call_async(IsPathValid.Request(path=path))
    wait_until(answered.done, 10.0, "is_path_valid answered during the search")
    cancel = handle.cancel_goal_async()
    wait_until(cancel.done, 10.0, "the cancel response")
    status, result = get_result(handle, 10.0)
    assert status == GoalStatus.STATUS_CANCELED
    assert not result.path.poses
    status, result = plan(client, goal_pose(2.0, 0.0), "GridBased")
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg


def test_is_path_valid_flags_poses_on_obstacles(planner: Any) -> None:
    probe, _, _, _ = planner
    client = probe.create_client(IsPathValid, "is_path_valid")
    wait_until(client.service_is_ready, 10.0, "is_path_valid")
    path = Path()
    path.header.frame_id = "map"
    path.poses = [goal_pose(-1.5, -0.5), goal_pose(0.0, 0.0), goal_pose(0.5, 0.5)]
    future = client.call_async(IsPathValid.Request(path=path))
    wait_until(future.done, 10.0, "is_path_valid response")
    response = future.result()
    assert not response.is_valid
    assert list(response.invalid_pose_indices) == [1]


def test_map_pillars_are_where_the_sim_has_them() -> None:
    """Guards the test geometry: the centre pillar is occupied in the map the tests publish."""
    loaded = load_map(MAP_YAML)
    mx, my = loaded.spec.world_to_cell(0.0, 0.0)
    assert loaded.data[my, mx] == 100


def _set(probe: Node, name: str, value: float) -> SetParameters.Response:
    """Set one planner_server parameter over its service, as ``ros2 param set`` does."""
    client = probe.create_client(SetParameters, "/planner_server/set_parameters")
    assert client.wait_for_service(10.0)
    request = SetParameters.Request(parameters=[Parameter(name, value=value).to_parameter_msg()])
    future = client.call_async(request)
    wait_until(future.done, 10.0, f"setting {name}")
    return future.result()


def test_tolerance_set_at_run_time_changes_the_next_plan(planner: Any) -> None:
    """(0, 0) is inside the centre pillar: NavFn plans to the nearest free cell within ``tolerance``
    (0.5 m, Nav2's yaml), and refuses it with GOAL_OCCUPIED once the tolerance is 0."""
    probe, _, _, client = planner
    status, result = plan(client, goal_pose(0.0, 0.0), "GridBased")
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    assert _set(probe, "GridBased.tolerance", 0.0).results[0].successful
    status, result = plan(client, goal_pose(0.0, 0.0), "GridBased")
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, Codes.GOAL_OCCUPIED), result.error_msg
    refused = _set(probe, "GridBased.tolerance", -1.0).results[0]
    assert not refused.successful and "GridBased.tolerance=-1.0" in refused.reason
    assert _set(probe, "GridBased.tolerance", 0.5).results[0].successful
    status, result = plan(client, goal_pose(0.0, 0.0), "GridBased")
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
