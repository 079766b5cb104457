"""waypoint_follower over rclpy against a scripted navigate_to_pose: order, missed waypoints with
their error codes, stop_on_failure, loops and goal_index, feedback, cancel, empty goals."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from nav2_msgs.action import FollowWaypoints
from rclpy.parameter import Parameter

from nav_stack.ros.navigator.waypoint_follower import WaypointFollower
from tests.helpers.nav_ros_bt_fakes import FakeNavigateToPose, nav_goal
from tests.helpers.nav_ros_bt_rig import Rig, start_rig, stop_rig

pytestmark = pytest.mark.ros

POINTS = [(1.0, 0.0), (2.0, 0.0), (3.0, 1.0)]


def _rig(context, stop_on_failure: bool) -> Rig:
    overrides = [Parameter("stop_on_failure", value=stop_on_failure),
                 Parameter("wait_at_waypoint.waypoint_pause_duration", value=50)]
    return start_rig(context, lambda **kw: WaypointFollower(parameter_overrides=overrides, **kw))


@pytest.fixture
def rig(ros_context) -> Iterator[Rig]:
    rig = _rig(ros_context, stop_on_failure=False)
    rig.navigator = FakeNavigateToPose(context=ros_context)
    rig.executor.add_node(rig.navigator)
    try:
        yield rig
    finally:
        stop_rig(rig)
        rig.navigator.destroy_node()


def _goal(points=POINTS, index: int = 0, loops: int = 0) -> FollowWaypoints.Goal:
    return FollowWaypoints.Goal(poses=[nav_goal(x, y).pose for x, y in points], goal_index=index,
                                number_of_loops=loops)


def test_follows_all_waypoints_in_order_with_feedback(rig):
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    result = rig.result(rig.send(client, _goal()))
    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert rig.navigator.goals == POINTS
    assert [f.current_waypoint for f in rig.feedback] == [0, 1, 2]
    assert list(result.result.missed_waypoints) == []


def test_missed_waypoints_are_reported_and_the_rest_followed(rig):
    rig.navigator.failing.add((2.0, 0.0))
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    result = rig.result(rig.send(client, _goal()))
    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert rig.navigator.goals == POINTS
    [missed] = result.result.missed_waypoints
    assert (missed.index, missed.error_code, missed.goal.pose.position.x) == (1, 208, 2.0)


def test_goal_index_and_loops(rig):
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    assert rig.result(rig.send(client, _goal(index=1, loops=1))).status == GoalStatus.STATUS_SUCCEEDED
    assert rig.navigator.goals == POINTS[1:] + POINTS


def test_a_navigator_seen_once_is_not_asked_for_again_before_each_waypoint(rig):
    """rmw_fastrtps calls a server unavailable while the graph holds unequal numbers of request readers
    and response writers (another navigator coming or going): no waypoint may be missed to that."""
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    handle = rig.send(client, _goal())
    rig.wait(lambda: len(rig.navigator.goals) == 1, "the first navigation")
    rig.node._nav.server_is_ready = lambda: False  # the graph glitches from now on
    result = rig.result(handle)
    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert list(result.result.missed_waypoints) == []
    assert rig.navigator.goals == POINTS


def test_cancel_cancels_the_running_navigation(rig):
    rig.navigator.hold = True
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    handle = rig.send(client, _goal())
    rig.wait(lambda: len(rig.navigator.goals) == 1, "the first navigation")
    cancel = handle.cancel_goal_async()
    rig.wait(cancel.done, "the cancel response")
    assert rig.result(handle).status == GoalStatus.STATUS_CANCELED
    rig.wait(lambda: rig.navigator.canceled == 1, "the navigation to be canceled")


def test_empty_goal_is_aborted_with_no_valid_waypoints(rig):
    client = rig.action_client(FollowWaypoints, "follow_waypoints")
    result = rig.result(rig.send(client, _goal(points=[])))
    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == FollowWaypoints.Result.NO_VALID_WAYPOINTS


def test_stop_on_failure_aborts_at_the_first_missed_waypoint(ros_context):
    rig = _rig(ros_context, stop_on_failure=True)
    navigator = FakeNavigateToPose(context=ros_context)
    rig.executor.add_node(navigator)
    try:
        navigator.failing.add((1.0, 0.0))
        client = rig.action_client(FollowWaypoints, "follow_waypoints")
        result = rig.result(rig.send(client, _goal()))
        assert result.status == GoalStatus.STATUS_ABORTED
        assert result.result.error_code == FollowWaypoints.Result.STOP_ON_MISSED_WAYPOINT
        assert [m.index for m in result.result.missed_waypoints] == [0]
        assert navigator.goals == POINTS[:1]
    finally:
        stop_rig(rig)
        navigator.destroy_node()
