"""bt_navigator's localization guard against scripted Nav2 servers: a goal is refused while amcl_pose
is too uncertain or amcl reports degraded localization, accepted once it is trusted again, and a
running goal ends when the pose stays untrusted past the grace period; with no localization
messages at all (SLAM) nothing is refused."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.action import NavigateToPose
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher

from nav_stack.ros.bt_nodes.navigators import has_robot_pose
from nav_stack.ros.common.conversions import pose_from_2d
from nav_stack.ros.common.qos import DEFAULT, LATCHED
from nav_stack.ros.localization.amcl_messages import LOCALIZATION_STATUS
from nav_stack.ros.navigator.bt_navigator import UNKNOWN, BtNavigator
from tests.helpers.nav_ros_bt_fakes import nav_goal
from tests.helpers.nav_ros_bt_rig import NAVIGATOR_OVERRIDES, Rig, start_rig, stop_rig

pytestmark = pytest.mark.ros
GRACE = 0.5  # s (wall here: the rig runs without sim time)


@pytest.fixture
def overrides() -> list[Parameter]:
    return [Parameter("localization_grace_period", value=GRACE)]


@pytest.fixture
def rig(ros_context, overrides: list[Parameter]) -> Iterator[Rig]:
    params = [*NAVIGATOR_OVERRIDES, *overrides]
    rig = start_rig(ros_context, lambda context: BtNavigator(context=context, parameter_overrides=params))
    try:
        rig.wait(lambda: has_robot_pose(rig.node.robot), "the fake robot pose in bt_navigator's TF buffer")
        yield rig
    finally:
        stop_rig(rig)


@pytest.fixture
def amcl_pose(rig: Rig) -> Publisher:
    """The test's amcl_pose publisher (latched, as amcl's)."""
    return rig.client.create_publisher(PoseWithCovarianceStamped, "amcl_pose", LATCHED)


def _amcl_pose(variance: float) -> PoseWithCovarianceStamped:
    msg = PoseWithCovarianceStamped()
    msg.header.frame_id = "map"
    msg.pose.pose = pose_from_2d(0.0, 0.0, 0.0)
    msg.pose.covariance = [variance if i in (0, 7) else 0.01 if i == 35 else 0.0 for i in range(36)]
    return msg


def _publish_pose(rig: Rig, publisher: Publisher, variance: float, trusted: bool) -> None:
    """Publish an amcl_pose with ``variance`` (m²) in x and y and wait until the guard has taken it."""
    publisher.publish(_amcl_pose(variance))
    rig.wait(lambda: (rig.node.localization.trust() is None) == trusted, "the guard to take amcl_pose")


def _now(rig: Rig) -> float:
    return float(rig.node.get_clock().now().nanoseconds * 1e-9)


def test_a_goal_is_refused_while_amcl_pose_is_too_uncertain_and_accepted_once_it_is_tight(rig, amcl_pose):
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    _publish_pose(rig, amcl_pose, 4.0, trusted=False)  # σ 2 m: a global localization's cloud
    refused = rig.result(rig.send(client, nav_goal(1.0, 0.5)))

    assert refused.status == GoalStatus.STATUS_ABORTED
    assert refused.result.error_code == UNKNOWN
    assert refused.result.error_msg == ("navigate_to_pose: localization is not trustworthy: amcl_pose "
                                        "position σ 2.00 m > 1.00 m")
    assert rig.fake.count("compute_path_to_pose") == 0

    _publish_pose(rig, amcl_pose, 0.01, trusted=True)  # σ 0.1 m
    rig.fake.follow_steps = 5
    assert rig.result(rig.send(client, nav_goal(1.0, 0.5))).status == GoalStatus.STATUS_SUCCEEDED


def test_a_degraded_amcl_status_refuses_a_goal_with_amcls_cause(rig):
    cause = "few beams on walls: 3 of 60 beams returned within 3.5 m (< 20 %)"
    diagnostics = rig.client.create_publisher(DiagnosticArray, "/diagnostics", DEFAULT)

    def publish_until_taken() -> bool:  # /diagnostics is volatile: send until the guard has heard it
        diagnostics.publish(DiagnosticArray(status=[
            DiagnosticStatus(name="another_node: motors", level=DiagnosticStatus.ERROR, message="hot"),
            DiagnosticStatus(name=LOCALIZATION_STATUS, level=DiagnosticStatus.WARN, message=cause)]))
        return rig.node.localization.trust() is not None

    rig.wait(publish_until_taken, "the guard to take the WARN status")
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    refused = rig.result(rig.send(client, nav_goal(1.0, 0.5)))

    assert refused.status == GoalStatus.STATUS_ABORTED
    assert refused.result.error_code == UNKNOWN
    assert refused.result.error_msg == f"navigate_to_pose: localization is not trustworthy: {cause}"
    assert rig.fake.count("compute_path_to_pose") == 0


def test_a_running_goal_ends_when_the_pose_stays_untrusted_past_the_grace_period(rig, amcl_pose):
    rig.fake.hold_follow = True
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    handle = rig.send(client, nav_goal(1.0, 0.0))
    rig.wait(lambda: rig.fake.count("follow_path") >= 1, "a follow_path goal")
    before = _now(rig)
    _publish_pose(rig, amcl_pose, 4.0, trusted=False)
    result = rig.result(handle)

    assert _now(rig) - before > GRACE
    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == UNKNOWN
    assert result.result.error_msg == ("navigate_to_pose: localization is not trustworthy: amcl_pose "
                                       "position σ 2.00 m > 1.00 m")
    rig.wait(lambda: rig.fake.cancels.get("follow_path", 0) >= 1, "the controller goal canceled")


def test_with_no_localization_messages_the_guard_trusts_and_goals_succeed(rig):
    """SLAM publishes neither amcl_pose nor an amcl status: nothing may change."""
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    rig.fake.follow_steps = 5
    assert rig.result(rig.send(client, nav_goal(1.0, 0.5))).status == GoalStatus.STATUS_SUCCEEDED
    assert rig.node.localization.trust() is None


@pytest.mark.parametrize("overrides", [[Parameter("localization_topic", value="")]])
def test_an_empty_localization_topic_switches_the_guard_off(rig, amcl_pose):
    topics = {sub.topic_name for sub in rig.node.subscriptions}
    assert "/odom" in topics and not topics & {"/amcl_pose", "/diagnostics"}
    amcl_pose.publish(_amcl_pose(4.0))
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    rig.fake.follow_steps = 5
    assert rig.result(rig.send(client, nav_goal(1.0, 0.5))).status == GoalStatus.STATUS_SUCCEEDED
