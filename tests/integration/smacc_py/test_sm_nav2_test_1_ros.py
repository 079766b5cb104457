"""sm_nav2_test_1 on the real ROS runtime against FakeNav2: same sequences as the pure fake-client test."""

from __future__ import annotations

import itertools
import math

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from std_msgs.msg import UInt16

from navsuite_testing.ros import spin_until, wait_until
from smacc_py.state_machines.sm_nav2_test_1 import NOMINAL_TRANSITIONS, SmNav2Test1
from tests.integration.smacc_py.conftest import transition_keys

pytestmark = pytest.mark.ros


def _final(runtime) -> bool:  # type: ignore[no-untyped-def]
    return runtime.sm.current_state_names() == ["StFinalState"]


def test_success_path_matches_the_unit_sequence_and_uses_parameters(stack) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(SmNav2Test1, params={"waypoint_1": [1.5, 0.25, 0.0]})
    wait_until(lambda: _final(runtime), 30.0, "SmNav2Test1 to reach StFinalState")
    assert transition_keys(runtime) == list(NOMINAL_TRANSITIONS)
    goals = [g.pose.pose.position for g in fake.logs["navigate_to_pose"].goals]
    assert [(round(p.x, 3), round(p.y, 3)) for p in goals] == [(1.5, 0.25), (-0.55, 0.55)]
    assert fake.logs["navigate_to_pose"].goals[0].pose.header.frame_id == "map"
    assert fake.initial_poses and fake.initial_poses[0] == pytest.approx((-2.0, -0.5, 0.0))
    # CbPureSpinning turned the fake robot half a turn and stopped it.
    assert fake.twists[-1].angular.z == 0.0
    assert runtime.sm.get_global_sm_data("localization_attempt_count") == 0


def test_navigation_abort_takes_the_abort_transition_with_the_nav2_error(stack) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(SmNav2Test1, scripts={"navigate_to_pose": ["aborted"]})
    wait_until(lambda: _final(runtime), 30.0, "SmNav2Test1 to reach StFinalState")
    assert transition_keys(runtime) == [
        *NOMINAL_TRANSITIONS[:2],
        ("StNavigateToWaypoint1", "StFinalState", "ABORT"),
    ]
    event = runtime.sm.transition_log[-1].event
    assert (event.error_code, event.error_msg) == (204, "fake navigate_to_pose aborted as scripted")


def test_key_n_advances_all_sensors_go(stack, ros_context) -> None:  # type: ignore[no-untyped-def]
    _fake, runtime = stack(SmNav2Test1, bond_nodes=())
    probe = rclpy.create_node("key_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    try:
        pub = probe.create_publisher(UInt16, "/keyboard_unicode", 10)
        spin_until(
            executor,
            lambda: (
                runtime.sm.current_state_names() == ["StAllSensorsGo"] and pub.get_subscription_count() > 0
            ),
            10.0,
            "the machine and its keyboard subscription",
        )
        pub.publish(UInt16(data=ord("n")))
        spin_until(executor, lambda: bool(transition_keys(runtime)), 10.0, "a transition after key n")
        assert transition_keys(runtime)[0] == ("StAllSensorsGo", "StSetInitialPose", "NEXT")
    finally:
        executor.shutdown()
        probe.destroy_node()


def test_timer_fallback_then_retries_then_abort_on_sim_time(stack) -> None:  # type: ignore[no-untyped-def]
    # No bonds: StAllSensorsGo leaves on the 15 s (sim) timer. No AMCL: StSetInitialPose's
    # CbSetInitialPose publishes the pose every second and fails after 15 s each time, so after
    # 1 + 3 attempts EvMaxRetriesExceeded aborts.
    fake, runtime = stack(SmNav2Test1, bond_nodes=(), amcl_echo=False, clock_rate=100.0)
    wait_until(lambda: _final(runtime), 60.0, "the retries to run out")
    keys = transition_keys(runtime)
    assert keys == [
        ("StAllSensorsGo", "StSetInitialPose", "SUCCESS"),
        *[("StSetInitialPose", "StSetInitialPose", "ABORT")] * 4,
        ("StSetInitialPose", "StFinalState", "ABORT"),
    ]
    log = list(runtime.sm.transition_log)
    assert log[0].stamp_s - 1000.0 >= 15.0  # the timer ran on /clock, which starts at 1000 s
    # Each attempt lasts its 15 s of sim time, never less. The fake /clock runs 100x the wall clock
    # and does not wait for the machine, so a machine delayed by load notices the timeout late: a
    # 50 ms stall is 5 s of sim time. The upper bound only has to tell sim time from wall time, where
    # one attempt would span 1500 s of /clock.
    retries = itertools.pairwise(log[1:-1])
    assert all(14.9 <= later.stamp_s - earlier.stamp_s <= 60.0 for earlier, later in retries)
    # republished during each attempt (one per second of sim time when the machine keeps up with the
    # fake clock; fewer when load makes /clock jump by seconds between two of its polls)
    assert len(fake.initial_poses) >= 5 * 2
    assert all(pose == pytest.approx((-2.0, -0.5, 0.0)) for pose in fake.initial_poses)
    assert math.isclose(runtime.sm.get_global_sm_data("localization_attempt_count"), 5)
