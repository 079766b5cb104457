"""The pure part of sm_nav2_gazebo_test_1 (real Jazzy package, reference/smacc2.md §2) on scripted fakes.

States, orthogonals, behaviors, tags and the retry counter mirror the real package: NAV2_READY, the
15 s timer fallback, key N, RETRY self-transitions counted in global data with EvMaxRetriesExceeded →
ABORT after 1 + 3 attempts. Each test asserts the exact (source, target, tag) sequence.
"""


from __future__ import annotations

import logging
import math

import pytest

from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvActionAborted,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvTimer,
    SmaccEvent,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
    key_press_event,
)
from tests.helpers.smacc_fake_nav import (
    CbDefaultKeyboardBehavior,
    CbNavigateGlobalPosition,
    CbPureSpinning,
    CbTimerCountdownOnce,
    CbWaitNav2Nodes,
    ClKeyboard,
    ClNav2Z,
    CpAmcl,
    NavScript,
    OrKeyboard,
    OrNavigation,
    OrTimer,
)

log = logging.getLogger("sm_nav2_test_1")


class NAV2_READY(SUCCESS):
    pass


class NEXT(SUCCESS):
    pass


class RETRY(SUCCESS):
    pass


class EvMaxRetriesExceeded(SmaccEvent):
    pass


class FakeClock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


class SmNav2Test1(SmaccStateMachineBase):
    initial_state = "StAllSensorsGo"

    def __init__(self, script: NavScript, clock: FakeClock) -> None:
        self.nav_script = script
        super().__init__(now=clock)

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTimer)
        self.create_orthogonal(OrKeyboard)
        self.create_orthogonal(OrNavigation)


class StAllSensorsGo(SmaccState, parent=SmNav2Test1):
    reactions = [
        Transition(EvCbSuccess[CbWaitNav2Nodes, OrNavigation], "StSetInitialPose", NAV2_READY),
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StSetInitialPose", SUCCESS),
        Transition(key_press_event("N")[CbDefaultKeyboardBehavior, OrKeyboard], "StSetInitialPose", NEXT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbWaitNav2Nodes)
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, 15.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StSetInitialPose(SmaccState, parent=SmNav2Test1):
    MAX_RETRIES = 3
    MAX_ATTEMPTS = 1 + MAX_RETRIES
    ATTEMPT_COUNTER_KEY = "localization_attempt_count"

    reactions = [
        Transition(EvCbSuccess[CbWaitNav2Nodes, OrNavigation], "StNavigateToWaypoint1", SUCCESS),
        Transition(EvCbFailure[CbWaitNav2Nodes, OrNavigation], "StSetInitialPose", RETRY),
        Transition(EvMaxRetriesExceeded[CbWaitNav2Nodes, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbWaitNav2Nodes)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)

    def runtime_configure(self) -> None:
        attempts = self.get_global_sm_data(self.ATTEMPT_COUNTER_KEY, 0) + 1
        self.set_global_sm_data(self.ATTEMPT_COUNTER_KEY, attempts)
        if attempts > self.MAX_ATTEMPTS:
            self.post_event(EvMaxRetriesExceeded[CbWaitNav2Nodes, OrNavigation])
            return
        self.requires_client(ClNav2Z).get_component(CpAmcl).set_initial_pose(-2.0, -0.5, 0.0)

    def on_exit_SUCCESS(self) -> None:
        self.set_global_sm_data(self.ATTEMPT_COUNTER_KEY, 0)

    def on_exit_ABORT(self) -> None:
        log.error("StSetInitialPose: localization failed after max retries, aborting")


class StNavigateToWaypoint1(SmaccState, parent=SmNav2Test1):
    reactions = [
        Transition(EvActionSucceeded[ClNav2Z, OrNavigation], "StRotate", SUCCESS),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, 2.0, 0.0, 0.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StRotate(SmaccState, parent=SmNav2Test1):
    reactions = [
        Transition(EvCbSuccess[CbPureSpinning, OrNavigation], "StNavigateToWaypoint2", SUCCESS),
        Transition(EvCbFailure[CbPureSpinning, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbPureSpinning, math.pi, 0.5)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StNavigateToWaypoint2(SmaccState, parent=SmNav2Test1):
    reactions = [
        Transition(EvActionSucceeded[ClNav2Z, OrNavigation], "StFinalState", SUCCESS),
        Transition(EvActionAborted[ClNav2Z, OrNavigation], "StFinalState", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, 0.0, 0.0, 0.0)
        cls.configure_orthogonal(OrKeyboard, CbDefaultKeyboardBehavior)


class StFinalState(SmaccState, parent=SmNav2Test1):
    def on_entry(self) -> None:
        log.info("Mission Complete")


def _run(script: NavScript) -> tuple[SmNav2Test1, FakeClock]:
    clock = FakeClock()
    sm = SmNav2Test1(script, clock)
    sm.start()
    sm.process_events()
    return sm, clock


def _keys(sm: SmaccStateMachineBase) -> list[tuple[str, str, str]]:
    return [record.key() for record in sm.transition_log]


TAIL = [
    ("StNavigateToWaypoint1", "StRotate", "SUCCESS"),
    ("StRotate", "StNavigateToWaypoint2", "SUCCESS"),
    ("StNavigateToWaypoint2", "StFinalState", "SUCCESS"),
]


def test_nominal_mission_goes_nav2_ready_then_through_both_waypoints() -> None:
    sm, _ = _run(NavScript(readiness=("success", "success"), goals=("succeeded", "succeeded"),
                           spins=("success",)))
    assert _keys(sm) == [
        ("StAllSensorsGo", "StSetInitialPose", "NAV2_READY"),
        ("StSetInitialPose", "StNavigateToWaypoint1", "SUCCESS"),
        *TAIL,
    ]
    nav = sm.requires_client(ClNav2Z)
    assert nav.goals_sent == [(2.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
    assert nav.get_component(CpAmcl).initial_poses == [(-2.0, -0.5, 0.0)]
    assert sm.current_state_names() == ["StFinalState"]
    assert sm.get_global_sm_data("localization_attempt_count") == 0  # reset by on_exit_SUCCESS


def test_timer_fallback_fires_after_15_s_of_machine_clock() -> None:
    sm, clock = _run(NavScript(readiness=("pending", "success"), goals=("succeeded", "succeeded"),
                               spins=("success",)))
    clock.t = 14.9
    sm.update()
    sm.process_events()
    assert _keys(sm) == []
    clock.t = 15.0
    sm.update()
    sm.process_events()
    assert _keys(sm)[0] == ("StAllSensorsGo", "StSetInitialPose", "SUCCESS")
    assert _keys(sm)[1:] == [("StSetInitialPose", "StNavigateToWaypoint1", "SUCCESS"), *TAIL]


def test_key_n_advances_from_all_sensors_go_only() -> None:
    sm, _ = _run(NavScript(readiness=("pending", "pending")))
    keyboard = sm.requires_client(ClKeyboard)
    keyboard.press("n")
    sm.process_events()
    assert _keys(sm) == [("StAllSensorsGo", "StSetInitialPose", "NEXT")]
    keyboard.press("n")  # StSetInitialPose has no key transition: the event is unhandled
    sm.process_events()
    assert sm.current_state_names() == ["StSetInitialPose"]


def test_retries_then_aborts_after_four_attempts() -> None:
    sm, _ = _run(NavScript(readiness=("success", "failure", "failure", "failure", "failure")))
    assert _keys(sm) == [
        ("StAllSensorsGo", "StSetInitialPose", "NAV2_READY"),
        *[("StSetInitialPose", "StSetInitialPose", "RETRY")] * 4,
        ("StSetInitialPose", "StFinalState", "ABORT"),
    ]
    assert len(sm.requires_client(ClNav2Z).get_component(CpAmcl).initial_poses) == 4
    assert sm.get_global_sm_data("localization_attempt_count") == 5  # on_exit_SUCCESS never ran


def test_retry_then_success_resets_the_counter_only_on_exact_success_tag() -> None:
    sm, _ = _run(NavScript(readiness=("success", "failure", "success"), goals=("succeeded", "succeeded"),
                           spins=("success",)))
    assert _keys(sm)[:3] == [
        ("StAllSensorsGo", "StSetInitialPose", "NAV2_READY"),
        ("StSetInitialPose", "StSetInitialPose", "RETRY"),
        ("StSetInitialPose", "StNavigateToWaypoint1", "SUCCESS"),
    ]
    assert sm.get_global_sm_data("localization_attempt_count") == 0


@pytest.mark.parametrize(
    ("goals", "spins", "last"),
    [
        (("aborted",), (), ("StNavigateToWaypoint1", "StFinalState", "ABORT")),
        (("succeeded",), ("failure",), ("StRotate", "StFinalState", "ABORT")),
        (("succeeded", "aborted"), ("success",), ("StNavigateToWaypoint2", "StFinalState", "ABORT")),
    ],
)
def test_navigation_failures_abort_to_final_state(goals: tuple[str, ...], spins: tuple[str, ...],
                                                  last: tuple[str, str, str]) -> None:
    sm, _ = _run(NavScript(readiness=("success", "success"), goals=goals, spins=spins))
    assert _keys(sm)[-1] == last
    assert sm.current_state_names() == ["StFinalState"]
