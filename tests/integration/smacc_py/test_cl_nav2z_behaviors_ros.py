"""cl_nav2z, cl_ros2_timer and cl_keyboard behaviors on the real runtime against FakeNav2."""

from __future__ import annotations

import math

import pytest
import rclpy
from geometry_msgs.msg import Twist
from rclpy.executors import SingleThreadedExecutor
from std_msgs.msg import UInt16

from nav_stack.ros.common.selectors import Selector
from navsuite_testing.ros import spin_until, wait_until
from smacc_py.clients.cl_nav2z import CpGoalCheckerSwitcher, CpOdomTracker, CpPlannerSwitcher
from tests.integration.smacc_py import machines as m
from tests.integration.smacc_py.conftest import transition_keys

pytestmark = pytest.mark.ros


def _leaf(runtime) -> str:  # type: ignore[no-untyped-def]
    names = runtime.sm.current_state_names()
    return names[-1] if names else ""


def _wait_leaf(runtime, names: set[str], timeout: float = 20.0) -> str:  # type: ignore[no-untyped-def]
    wait_until(lambda: _leaf(runtime) in names, timeout, f"the machine to reach one of {sorted(names)}")
    return _leaf(runtime)


def test_pure_spinning_turns_then_ends_with_a_zero_twist(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmSpin, clock_rate=2.0)  # slow clock: a loaded CPU cannot make it overshoot
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"
    assert any(t.angular.z > 0.0 for t in fake.twists)
    assert max(t.angular.z for t in fake.twists) <= 0.5
    # The final zero twist may still be on its way over DDS when the state machine has moved on.
    wait_until(lambda: (fake.twists[-1].linear.x, fake.twists[-1].angular.z) == (0.0, 0.0), 5.0,
               "the final zero twist")
    assert fake.map_pose()[2] == pytest.approx(math.pi / 2, abs=0.2)


def test_pure_spinning_fails_on_timeout_and_stops_the_robot(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmSpin, frozen=True)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StFailed"
    event = runtime.sm.transition_log[-1].event
    assert "timed out after 8.0 s" in event.reason
    assert runtime.sm.transition_log[-1].stamp_s - 1000.0 >= 8.0  # measured on sim time
    assert any(t.angular.z != 0.0 for t in fake.twists)
    wait_until(lambda: fake.twists[-1].angular.z == 0.0, 5.0, "the final zero twist")


def test_pure_spinning_stops_the_robot_when_its_state_exits_mid_spin(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmSpinInterrupted)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"  # left on the timer, not the spin
    assert runtime.sm.transition_log[-1].stamp_s - 1000.0 >= m.SPIN_INTERRUPT_S
    assert any(t.angular.z > 0.0 for t in fake.twists)  # it was turning
    wait_until(lambda: fake.twists and fake.twists[-1].angular.z == 0.0, 5.0, "the zero twist on exit")
    published, yaw = len(fake.twists), fake.map_pose()[2]
    assert 0.0 < yaw < 2 * math.pi - 0.5  # cut short well before the full turn
    # Ten control periods of sim time later, the behavior has published nothing more: its loop ended.
    until_s = fake.sim_s + 1.0
    wait_until(lambda: fake.sim_s > until_s, 10.0, "1 s of sim time after the exit")
    assert len(fake.twists) == published
    assert fake.map_pose()[2] == pytest.approx(yaw)


def test_switchers_publish_latched_selections_nav_stack_reads(stack, ros_context) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(m.SmSelectors)
    _wait_leaf(runtime, {"StIdle"})
    planner = runtime.sm.requires_component(CpPlannerSwitcher)
    checker = runtime.sm.requires_component(CpGoalCheckerSwitcher)
    planner.set_default_planners()  # before anybody subscribes: transient local must keep them
    checker.set_goal_checker_id()
    with pytest.raises(ValueError, match="preset 'forward' selects planner 'ForwardGlobalPlanner'"):
        planner.set_preset("forward")
    probe = rclpy.create_node("selector_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    try:
        # nav_stack's own subscriber (planner_server, controller_server and bt_navigator use it).
        topics = ("planner_selector", "controller_selector", "goal_checker_selector")
        selectors = [Selector(probe, topic) for topic in topics]

        def selected() -> list[str]:
            return [selector.selected for selector in selectors]

        spin_until(executor, lambda: selected() == ["GridBased", "FollowPath", "goal_checker"], 10.0,
                   "the selections published before the probe existed")
        assert {probe.resolve_topic_name(t) for t in topics} == {f"/{t}" for t in topics}
        planner.set_desired_global_planner("ThetaStar")
        planner.set_desired_controller("DWB")
        planner.commit_publish()
        checker.set_goal_checker_id("stopped_goal_checker")
        spin_until(executor, lambda: selected() == ["ThetaStar", "DWB", "stopped_goal_checker"], 10.0,
                   "the new selections")
    finally:
        executor.shutdown()
        probe.destroy_node()


def test_wait_nav2_nodes_fails_on_timeout_naming_the_missing_node(stack) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(m.SmWaitNodes, bond_nodes=("planner_server", "controller_server"))
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StFailed"
    assert "bt_navigator" in runtime.sm.transition_log[-1].event.reason
    assert "planner_server" not in runtime.sm.transition_log[-1].event.reason


def test_wait_nav2_nodes_succeeds_when_every_bond_is_active(stack) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(m.SmWaitNodes)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"


def test_navigation_goal_is_cancelled_when_its_state_exits(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmCancelOnExit, scripts={"navigate_to_pose": ["hold"]})
    assert _wait_leaf(runtime, {"StAfter", "StFailed"}) == "StAfter"
    wait_until(
        lambda: fake.logs["navigate_to_pose"].results == ["canceled"], 10.0, "the goal to be cancelled"
    )
    assert fake.logs["navigate_to_pose"].cancels == 1
    nav = runtime.sm.requires_client(m.ClNav2Z)
    wait_until(lambda: not nav.action_client("navigate_to_pose").active_tickets(), 5.0, "the ticket to end")
    assert _leaf(runtime) == "StAfter"  # the disowned goal's EvActionCancelled was never posted


def test_relative_motions_send_the_behavior_server_goals(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmMotions)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"
    drive, backup = fake.logs["drive_on_heading"].goals, fake.logs["backup"].goals
    assert [(g.target.x, g.speed) for g in drive] == [pytest.approx((0.5, 0.2))]
    assert [(g.target.x, g.speed) for g in backup] == [pytest.approx((0.3, 0.15))]
    spins = [g.target_yaw for g in fake.logs["spin"].goals]
    assert spins == [pytest.approx(math.pi / 2), pytest.approx(math.pi, abs=1e-3)]  # relative, then absolute
    assert transition_keys(runtime)[-1] == ("StAbort", "StDone", "SUCCESS")
    assert runtime.sm.transition_log[-1].event.goals_canceling == 0  # the server answered the cancel-all


def test_set_initial_pose_succeeds_once_amcl_reports_it(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmInitialPose)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"
    assert fake.initial_poses[0] == pytest.approx((-2.0, -0.5, 0.0))


def test_set_initial_pose_fails_when_amcl_stays_silent(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmInitialPose, amcl_echo=False, clock_rate=50.0)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StFailed"
    assert len(fake.initial_poses) >= 10  # republished every second of the 15 s timeout
    assert "did not report" in runtime.sm.transition_log[-1].event.reason


@pytest.mark.parametrize(("turn", "expected_action"), [(0.0, "backup"), (0.6, "follow_path")])
def test_undo_path_backwards_undoes_the_recorded_motion(stack, ros_context, turn, expected_action) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmUndo, scripts={"navigate_to_pose": ["hold"]})
    probe = rclpy.create_node("undo_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    try:
        pub = probe.create_publisher(UInt16, "/keyboard_unicode", 10)
        spin_until(
            executor,
            lambda: (
                _leaf(runtime) == "StRecord"
                and len(fake.logs["navigate_to_pose"].goals) == 1
                and pub.get_subscription_count() > 0
            ),
            10.0,
            "StRecord with its goal running",
        )
        fake.cmd = Twist()
        fake.cmd.linear.x, fake.cmd.angular.z = 0.5, turn
        spin_until(executor, lambda: math.hypot(*fake.map_pose()[:2]) > 0.6, 10.0, "the robot to move 0.6 m")
        fake.cmd = Twist()
        tracker = runtime.sm.requires_component(CpOdomTracker)

        def tracker_saw_the_stop() -> bool:  # odometry is best effort and the SM's executor may lag
            seen = tracker.last_pose
            return seen is not None and math.dist(seen[:2], fake.odom_pose[:2]) < 0.005

        spin_until(executor, tracker_saw_the_stop, 10.0, "the tracker to see the robot stopped")
        recorded = tracker.path()
        assert len(recorded) >= 5
        pub.publish(UInt16(data=ord("u")))
        spin_until(executor, lambda: _leaf(runtime) in {"StDone", "StFailed"}, 10.0, "the undo to finish")
        assert _leaf(runtime) == "StDone"
        assert fake.logs["navigate_to_pose"].cancels == 1
        goals = fake.logs[expected_action].goals
        assert len(goals) == 1
        stopped_at = fake.odom_pose  # the path ends where the robot stopped (odom frame)
        if expected_action == "backup":
            assert goals[0].target.x == pytest.approx(math.dist(recorded[0][:2], stopped_at[:2]), abs=0.05), (
                recorded
            )
        else:
            poses = [p.pose.position for p in goals[0].path.poses]
            assert (poses[0].x, poses[0].y) == pytest.approx(stopped_at[:2], abs=0.02)
            assert (poses[-1].x, poses[-1].y) == pytest.approx(recorded[0][:2], abs=0.02)
        assert tracker.path() == []  # popped after success
    finally:
        executor.shutdown()
        probe.destroy_node()


def test_waypoint_navigator_walks_the_list_and_posts_final(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(m.SmWaypoints)
    assert _wait_leaf(runtime, {"StDone", "StFailed"}) == "StDone"
    goals = [(g.pose.pose.position.x, g.pose.pose.position.y) for g in fake.logs["navigate_to_pose"].goals]
    assert goals == [(1.0, 0.0), (2.0, 0.5)]
    assert [k[2] for k in transition_keys(runtime)] == ["SUCCESS", "SUCCESS"]


def test_timer_loop_ticks_on_sim_time(stack) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(m.SmTimerLoop)
    assert _wait_leaf(runtime, {"StDone"}) == "StDone"
    assert runtime.sm.transition_log[-1].stamp_s - 1000.0 >= 6.0  # three 2 s ticks of /clock
