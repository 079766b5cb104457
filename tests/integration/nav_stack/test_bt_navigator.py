"""bt_navigator over rclpy against scripted Nav2 servers: the default trees, results with the failing
server's code, cancel, preemption, bad trees, goal_pose, selectors, feedback and the BT log."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import FollowPath, NavigateThroughPoses, NavigateToPose
from nav2_msgs.msg import BehaviorTreeLog
from rclpy.parameter import Parameter
from std_msgs.msg import String

from nav_stack.ros.bt_nodes.navigators import TF_ERROR, UNKNOWN, has_robot_pose
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.navigator.bt_navigator import FAILED_TO_LOAD_BEHAVIOR_TREE, BtNavigator
from tests.helpers.nav_ros_bt_fakes import nav_goal
from tests.helpers.nav_ros_bt_rig import NAVIGATOR_OVERRIDES, Rig, start_rig, stop_rig

pytestmark = pytest.mark.ros


@pytest.fixture
def rig(ros_context) -> Iterator[Rig]:
    rig = start_rig(ros_context, lambda context: BtNavigator(context=context,
                                                             parameter_overrides=NAVIGATOR_OVERRIDES))
    try:
        # The fake's map -> base_link is latched, but it reaches the navigator's TF buffer only after
        # discovery; a goal sent before that fails the tree's first pose lookup (RemovePassedGoals).
        rig.wait(lambda: _has_robot_pose(rig.node), "the fake robot pose in bt_navigator's TF buffer")
        yield rig
    finally:
        stop_rig(rig)


def _has_robot_pose(node: BtNavigator) -> bool:
    return has_robot_pose(node.robot)


def test_navigate_to_pose_plans_follows_and_succeeds_with_feedback_and_bt_log(rig):
    logs: list[BehaviorTreeLog] = []
    rig.client.create_subscription(BehaviorTreeLog, "behavior_tree_log", logs.append, 100)
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    rig.fake.follow_steps = 60
    result = rig.result(rig.send(client, nav_goal(1.0, 0.5)))

    assert result.status == GoalStatus.STATUS_SUCCEEDED
    assert result.result.error_code == 0
    plan_goal = rig.fake.goals["compute_path_to_pose"][0]
    assert (plan_goal.goal.pose.position.x, plan_goal.goal.pose.position.y) == (1.0, 0.5)
    assert plan_goal.planner_id == "GridBased"
    follow_goal = rig.fake.goals["follow_path"][0]
    assert follow_goal.controller_id == "FollowPath"
    assert follow_goal.path.poses[-1].pose.position.x == pytest.approx(1.0)
    assert rig.feedback, "no feedback"
    last = rig.feedback[-1]
    assert last.current_pose.header.frame_id == "map"
    assert last.distance_remaining == pytest.approx(1.118, abs=0.01)  # robot at the path start
    rig.wait(lambda: any(e.node_name == "FollowPath" and e.current_status == "SUCCESS"
                         for log in logs for e in log.event_log), "FollowPath SUCCESS in the BT log")


def test_planner_failure_code_and_message_are_surfaced_in_the_result(rig):
    rig.fake.occupied.add((0.0, 0.0))
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    result = rig.result(rig.send(client, nav_goal(0.0, 0.0)))

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == 206
    assert "GOAL_OCCUPIED" in result.result.error_msg
    assert "compute_path_to_pose" in result.result.error_msg
    assert "occupied cell" in result.result.error_msg
    assert rig.fake.count("spin") == 0, "no recovery can help an occupied goal"


@pytest.mark.parametrize(("frame", "says"), [("", "header.frame_id is empty"),
                                            ("nowhere", "cannot transform the goal from 'nowhere'")])
def test_a_goal_in_an_empty_or_unknown_frame_is_refused_with_tf_error(rig, frame, says):
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    result = rig.result(rig.send(client, nav_goal(1.0, 0.5, frame=frame)))

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == TF_ERROR, result.result.error_msg
    assert says in result.result.error_msg
    assert rig.fake.count("compute_path_to_pose") == 0


def test_a_goal_before_the_robot_pose_is_known_is_refused_with_tf_error(ros_context):
    rig = start_rig(ros_context, lambda context: BtNavigator(context=context,
                                                             parameter_overrides=NAVIGATOR_OVERRIDES),
                    robot_xy=None)
    try:
        client = rig.action_client(NavigateToPose, "navigate_to_pose")
        result = rig.result(rig.send(client, nav_goal(1.0, 0.5)))
    finally:
        stop_rig(rig)

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == TF_ERROR, result.result.error_msg
    assert "Initial robot pose is not available" in result.result.error_msg
    assert rig.fake.count("compute_path_to_pose") == 0


def test_controller_failures_run_the_recoveries_and_report_the_controller_code(rig):
    rig.fake.follow_steps = 1
    rig.fake.follow_codes = [105] * 20
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    result = rig.result(rig.send(client, nav_goal(1.0, 0.0)), timeout=60.0)

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == 105
    assert "follow_path" in result.result.error_msg
    assert rig.fake.count("spin") >= 1 and rig.fake.count("backup") >= 1 and rig.fake.count("wait") >= 1
    assert rig.fake.calls.get("local_costmap/clear_entirely_local_costmap", 0) >= 1
    assert max(f.number_of_recoveries for f in rig.feedback) >= 3


def test_a_leaf_failure_without_an_error_code_is_named_in_the_result(rig):
    """A rejected goal sets no server error code: the result still says which leaf failed, and how."""
    rig.fake.rejecting.add("follow_path")
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    result = rig.result(rig.send(client, nav_goal(1.0, 0.0)))

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == UNKNOWN
    assert "the goal was rejected by 'follow_path'" in result.result.error_msg, result.result.error_msg


def test_cancel_halts_the_tree_and_cancels_the_controller_goal(rig):
    rig.fake.hold_follow = True
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    handle = rig.send(client, nav_goal(1.0, 0.0))
    rig.wait(lambda: rig.fake.count("follow_path") >= 1, "a follow_path goal")
    cancel = handle.cancel_goal_async()
    rig.wait(cancel.done, "the cancel response")
    result = rig.result(handle)

    assert result.status == GoalStatus.STATUS_CANCELED
    rig.wait(lambda: rig.fake.cancels.get("follow_path", 0) >= 1, "follow_path cancel request")


def test_a_new_goal_preempts_the_running_one(rig):
    """The tree restarts: the running FollowPath is cancelled, and the next path followed is planned
    to the new goal (the old one, still followed, could end the new goal at the old place)."""
    rig.fake.hold_follow = True
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    first = rig.send(client, nav_goal(1.0, 0.0))
    rig.wait(lambda: rig.fake.count("follow_path") >= 1, "the first follow_path goal")
    second = rig.send(client, nav_goal(-1.0, 2.0))
    first_result = rig.result(first)
    assert first_result.status == GoalStatus.STATUS_ABORTED
    assert "preempted" in first_result.result.error_msg
    rig.wait(lambda: rig.fake.cancels.get("follow_path", 0) >= 1, "the old follow_path cancelled")
    rig.wait(lambda: rig.fake.count("follow_path") >= 2, "a follow_path goal for the new goal")
    end = rig.fake.goals["follow_path"][1].path.poses[-1].pose.position
    assert (end.x, end.y) == (-1.0, 2.0)
    rig.fake.hold_follow = False
    assert rig.result(second).status == GoalStatus.STATUS_SUCCEEDED


def test_a_tree_with_an_unknown_node_aborts_with_file_line_and_node(rig, tmp_path: Path):
    tree = tmp_path / "bad_tree.xml"
    tree.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="MainTree">\n'
                    '    <Sequence>\n      <FlyToTheMoon speed="1"/>\n    </Sequence>\n'
                    '  </BehaviorTree>\n</root>\n')
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    result = rig.result(rig.send(client, nav_goal(1.0, 0.0, behavior_tree=str(tree))))

    assert result.status == GoalStatus.STATUS_ABORTED
    assert result.result.error_code == FAILED_TO_LOAD_BEHAVIOR_TREE
    assert f"{tree}:4" in result.result.error_msg
    assert "FlyToTheMoon" in result.result.error_msg
    assert rig.fake.count("compute_path_to_pose") == 0


def test_goal_pose_topic_starts_a_navigation(rig):
    pub = rig.client.create_publisher(PoseStamped, "goal_pose", 10)
    rig.wait(lambda: pub.get_subscription_count() > 0, "bt_navigator's goal_pose subscription")
    pose = nav_goal(0.5, -0.5).pose
    pub.publish(pose)
    rig.wait(lambda: rig.fake.count("compute_path_to_pose") >= 1, "a plan requested by goal_pose")
    assert rig.fake.goals["compute_path_to_pose"][0].goal.pose.position.y == -0.5


def test_selector_topics_choose_the_planner_and_controller(rig):
    for topic, value in (("planner_selector", "ThetaStar"), ("controller_selector", "Precise")):
        rig.client.create_publisher(String, topic, LATCHED).publish(String(data=value))
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    rig.wait(lambda: rig.node.selectors("controller_selector") == "Precise", "the controller selection")
    rig.wait(lambda: rig.node.selectors("planner_selector") == "ThetaStar", "the planner selection")
    assert rig.result(rig.send(client, nav_goal(1.0, 0.0))).status == GoalStatus.STATUS_SUCCEEDED
    assert rig.fake.goals["compute_path_to_pose"][0].planner_id == "ThetaStar"
    assert rig.fake.goals["follow_path"][0].controller_id == "Precise"


def test_navigate_through_poses_plans_through_all_poses(rig):
    client = rig.action_client(NavigateThroughPoses, "navigate_through_poses")
    goal = NavigateThroughPoses.Goal()
    goal.poses = [nav_goal(1.0, 0.0).pose, nav_goal(2.0, 1.0).pose]
    result = rig.result(rig.send(client, goal))

    assert result.status == GoalStatus.STATUS_SUCCEEDED, (result.result.error_code, result.result.error_msg)
    planned = rig.fake.goals["compute_path_through_poses"][0]
    assert [(p.pose.position.x, p.pose.position.y) for p in planned.goals] == [(1.0, 0.0), (2.0, 1.0)]
    assert rig.feedback[-1].number_of_poses_remaining == 2


def test_a_broken_default_tree_fails_configuration(ros_context, tmp_path: Path):
    broken = tmp_path / "broken.xml"
    broken.write_text("<root BTCPP_format='4'><BehaviorTree ID='T'><Nope/></BehaviorTree></root>")
    node = BtNavigator(context=ros_context,
                       parameter_overrides=[Parameter("default_nav_to_pose_bt_xml", value=str(broken))])
    try:
        from lifecycle_msgs.msg import State
        from rclpy.lifecycle import TransitionCallbackReturn

        assert node.trigger_configure() == TransitionCallbackReturn.FAILURE
        assert node._state_machine.current_state[0] == State.PRIMARY_STATE_UNCONFIGURED
    finally:
        node.destroy_node()


def test_follow_path_receives_a_replanned_path_while_running(rig):
    rig.fake.hold_follow = True
    client = rig.action_client(NavigateToPose, "navigate_to_pose")
    handle = rig.send(client, nav_goal(1.0, 0.0))
    # The tree replans at 1 Hz of the node clock; each new path is sent to the controller.
    rig.wait(lambda: rig.fake.count("compute_path_to_pose") >= 2, "a replanned path", timeout=10.0)
    rig.wait(lambda: rig.fake.count("follow_path") >= 2, "the new path sent to follow_path", timeout=10.0)
    assert isinstance(rig.fake.goals["follow_path"][1], FollowPath.Goal)
    rig.fake.hold_follow = False
    assert rig.result(handle).status == GoalStatus.STATUS_SUCCEEDED
