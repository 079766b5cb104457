"""The shipped sm_nav2_test_1 (states, orthogonals, tags, retry logic) on scripted clients, without ROS.

The machine is ``SmNav2Test1`` itself; only its ROS-facing clients and components are replaced, through
``substitutes=``, by the stand-ins of tests/helpers/smacc_fake_nav.py. The nominal run must give
``NOMINAL_TRANSITIONS``, the sequence the integration test (FakeNav2 over DDS) and the system test (the
real stack) assert as well.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from smacc_py.clients.cl_nav2z import ClNav2Z, CpAmcl
from smacc_py.state_machines.sm_nav2_test_1 import (
    NOMINAL_TRANSITIONS,
    SmNav2Test1,
    SmNav2Test1Params,
    StSetInitialPose,
)
from tests.helpers.smacc_fake_nav import Nav2Script, ScriptedNav2

Mission = tuple[SmNav2Test1, ScriptedNav2]
OUTSIDE_THE_MAP = (6.0, 0.0, 0.0)


@pytest.fixture
def mission() -> Iterator[Callable[..., Mission]]:
    """``mission(config=..., **script)``: SmNav2Test1 started on a ScriptedNav2 world (stopped afterwards)."""
    worlds: list[ScriptedNav2] = []

    def start(config: SmNav2Test1Params | None = None, **script: Any) -> Mission:
        world = ScriptedNav2(Nav2Script(**script))
        worlds.append(world)
        return world.start(SmNav2Test1, config=config or SmNav2Test1Params()), world

    yield start
    for world in worlds:
        world.close()


def _keys(sm: SmNav2Test1) -> list[tuple[str, str, str]]:
    return [record.key() for record in sm.transition_log]


def _finished(sm: SmNav2Test1) -> Callable[[], bool]:
    return lambda: sm.current_state_names() == ["StFinalState"]


def test_nominal_mission_gives_the_nominal_transitions(mission: Callable[..., Mission]) -> None:
    sm, world = mission()
    assert world.drive(sm, _finished(sm))
    assert _keys(sm) == list(NOMINAL_TRANSITIONS)
    config = SmNav2Test1Params()
    goals = world.navigation_goals(sm)
    assert goals == [pytest.approx(config.waypoint_1), pytest.approx(config.waypoint_2)]
    assert sm.requires_component(CpAmcl).published == [config.initial_pose]
    # CbPureSpinning turned the robot half a turn (within its 0.1 rad tolerance) and stopped it.
    twists = world.base.twists
    assert max(t.angular.z for t in twists) == pytest.approx(0.5)
    assert (twists[-1].linear.x, twists[-1].angular.z) == (0.0, 0.0)
    assert sm.get_global_sm_data(StSetInitialPose.ATTEMPT_COUNTER_KEY) == 0  # reset by on_exit_SUCCESS


def test_waypoints_come_from_the_configuration(mission: Callable[..., Mission]) -> None:
    config = SmNav2Test1Params(waypoint_1=(1.5, 0.25, 0.0), waypoint_2=(0.5, -1.0, 1.0))
    sm, world = mission(config)
    assert world.drive(sm, _finished(sm))
    assert _keys(sm) == list(NOMINAL_TRANSITIONS)
    assert world.navigation_goals(sm) == [pytest.approx((1.5, 0.25, 0.0)), pytest.approx((0.5, -1.0, 1.0))]


def test_unreachable_waypoint_1_aborts_with_the_nav2_error(mission: Callable[..., Mission]) -> None:
    sm, world = mission(SmNav2Test1Params(waypoint_1=OUTSIDE_THE_MAP))
    assert world.drive(sm, _finished(sm))
    assert _keys(sm) == [*NOMINAL_TRANSITIONS[:2], ("StNavigateToWaypoint1", "StFinalState", "ABORT")]
    event = sm.transition_log[-1].event
    assert (event.error_code, event.error_msg) == (204, "Goal outside map")
    assert len(world.navigation_goals(sm)) == 1


@pytest.mark.parametrize(
    ("config", "script", "last"),
    [
        (SmNav2Test1Params(), {"robot_moves": False}, ("StRotate", "StFinalState", "ABORT")),
        (SmNav2Test1Params(waypoint_2=OUTSIDE_THE_MAP), {},
         ("StNavigateToWaypoint2", "StFinalState", "ABORT")),
    ],
    ids=["spin-times-out", "waypoint-2-unreachable"],
)
def test_later_failures_abort_to_the_final_state(
    mission: Callable[..., Mission], config: SmNav2Test1Params, script: dict[str, Any],
    last: tuple[str, str, str],
) -> None:
    sm, world = mission(config, **script)
    assert world.drive(sm, _finished(sm))
    keys = _keys(sm)
    assert keys[:-1] == list(NOMINAL_TRANSITIONS[: len(keys) - 1])
    assert keys[-1] == last


def test_waiting_for_nav2_holds_lockstep_until_the_bonds_are_seen(mission: Callable[..., Mission]) -> None:
    """CbWaitNav2Nodes asks a lockstep simulator to wait for the heartbeats themselves (they come
    on a wall timer), not only for their publisher, so Nav2 is up at the same sim time every run."""
    sm, world = mission()
    sm.process_events()
    (hold,) = sm.requires_client(ClNav2Z).bond_holds
    assert hold is not None and not hold()  # entered StAllSensorsGo, no heartbeat yet
    assert world.drive(sm, lambda: bool(sm.transition_log))
    assert _keys(sm)[0] == NOMINAL_TRANSITIONS[0]
    assert hold()  # every heartbeat seen: the simulator may step on


def test_timer_fallback_fires_after_15_s_of_machine_clock(mission: Callable[..., Mission]) -> None:
    sm, world = mission(bonds=(False, True))  # Nav2 silent in StAllSensorsGo only
    assert world.drive(sm, lambda: bool(sm.transition_log))
    first = sm.transition_log[0]
    assert first.key() == ("StAllSensorsGo", "StSetInitialPose", "SUCCESS")
    assert type(first.event).__name__ == "EvTimer[CbTimerCountdownOnce, OrTimer]"
    assert 15.0 <= first.stamp_s < 15.5
    assert world.drive(sm, _finished(sm))
    assert _keys(sm)[1:] == list(NOMINAL_TRANSITIONS[1:])


def test_key_n_advances_from_all_sensors_go_only(mission: Callable[..., Mission]) -> None:
    sm, world = mission(bonds=(False,), amcl_silent_until_s=math.inf)
    keyboard = world.keyboard(sm)
    keyboard.press("n")
    sm.process_events()
    assert _keys(sm) == [("StAllSensorsGo", "StSetInitialPose", "NEXT")]
    keyboard.press("n")  # StSetInitialPose has no key transition: the event is unhandled
    sm.process_events()
    assert sm.current_state_names() == ["StSetInitialPose"]


def test_localization_retries_then_max_retries_exceeded_aborts(mission: Callable[..., Mission]) -> None:
    """AMCL never confirms: each attempt times out after 15 s (machine clock), then the fifth entry aborts."""
    sm, world = mission(amcl_silent_until_s=math.inf)
    assert world.drive(sm, _finished(sm))
    assert _keys(sm) == [
        NOMINAL_TRANSITIONS[0],
        *[("StSetInitialPose", "StSetInitialPose", "ABORT")] * StSetInitialPose.MAX_ATTEMPTS,
        ("StSetInitialPose", "StFinalState", "ABORT"),
    ]
    retry = sm.transition_log[1].event
    assert type(retry).__name__ == "EvCbFailure[CbSetInitialPose, OrNavigation]"
    assert "AMCL did not report a pose near (-2.0, -0.5, 0.0) within 15.0 s" in retry.reason
    last = sm.transition_log[-1].event
    assert type(last).__name__ == "EvMaxRetriesExceeded[CbSetInitialPose, OrNavigation]"
    for first, second in itertools.pairwise(list(sm.transition_log)[1:-1]):
        assert second.stamp_s - first.stamp_s == pytest.approx(15.0, abs=1.0)
    assert set(sm.requires_component(CpAmcl).published) == {SmNav2Test1Params().initial_pose}
    assert sm.get_global_sm_data(StSetInitialPose.ATTEMPT_COUNTER_KEY) == StSetInitialPose.MAX_ATTEMPTS + 1
    assert world.navigation_goals(sm) == []


def test_retry_then_success_resets_the_counter_on_the_success_tag(mission: Callable[..., Mission]) -> None:
    """AMCL answers only from 20 s on: the first attempt fails at 15 s, the second succeeds."""
    sm, world = mission(amcl_silent_until_s=20.0)
    assert world.drive(sm, _finished(sm))
    assert _keys(sm) == [
        NOMINAL_TRANSITIONS[0],
        ("StSetInitialPose", "StSetInitialPose", "ABORT"),
        *NOMINAL_TRANSITIONS[1:],
    ]
    assert sm.transition_log[2].stamp_s >= 20.0
    assert sm.get_global_sm_data(StSetInitialPose.ATTEMPT_COUNTER_KEY) == 0



def test_the_machine_is_the_shipped_one_with_stand_in_clients(mission: Callable[..., Mission]) -> None:
    sm, _ = mission()
    nav = sm.requires_client(ClNav2Z)
    assert type(nav).__name__ == "ScriptedClNav2Z" and nav.client_type is ClNav2Z
    assert [type(o).__name__ for o in sm.orthogonals] == ["OrTimer", "OrKeyboard", "OrNavigation"]


def test_a_lost_navigator_is_retried_once_nav2_is_back(mission: Callable[..., Mission]) -> None:
    """Issue 45: the server watch ends the goal (9000, "server lost"); StRecoverNavigation1 waits for the
    bonds of the respawned stack and drives to
    the same waypoint again; the mission then ends as the nominal one."""
    sm, world = mission(navigate=("lost",))
    assert world.drive(sm, _finished(sm))
    keys = _keys(sm)
    assert keys[:3] == [*NOMINAL_TRANSITIONS[:2],
                        ("StNavigateToWaypoint1", "StRecoverNavigation1", "NAVIGATOR_LOST")]
    assert keys[3] == ("StRecoverNavigation1", "StNavigateToWaypoint1", "SUCCESS")
    assert keys[4:] == list(NOMINAL_TRANSITIONS[2:])
    config = SmNav2Test1Params()
    assert world.navigation_goals(sm) == [pytest.approx(config.waypoint_1)] * 2 + [
        pytest.approx(config.waypoint_2)]


def test_a_navigator_lost_again_and_again_aborts_after_the_retries(mission: Callable[..., Mission]) -> None:
    sm, world = mission(navigate=("lost",) * 3)
    assert world.drive(sm, _finished(sm))
    keys = _keys(sm)
    assert keys[-1] == ("StRecoverNavigation1", "StFinalState", "ABORT")
    assert keys.count(("StNavigateToWaypoint1", "StRecoverNavigation1", "NAVIGATOR_LOST")) == 3
    assert "at most 2 retries" in sm.transition_log[-1].event.reason


def test_an_ordinary_abort_is_not_retried(mission: Callable[..., Mission]) -> None:
    sm, world = mission(navigate=("aborted",))
    assert world.drive(sm, _finished(sm))
    assert _keys(sm)[-1] == ("StNavigateToWaypoint1", "StFinalState", "ABORT")
