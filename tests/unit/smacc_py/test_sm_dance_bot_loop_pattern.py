"""sm_dance_bot's loop_pattern: what a built inner state declares (the machine's own structure is in
test_sm_dance_bot_model.py)."""

from __future__ import annotations

from smacc_py.clients.cl_nav2z import CbAbsoluteRotate, CbNavigateForward
from smacc_py.core import (
    ABORT,
    CONTINUELOOP,
    ENDLOOP,
    SUCCESS,
    EvCbFailure,
    EvCbSuccess,
    EvLoopContinue,
    EvLoopEnd,
)
from smacc_py.state_machines.sm_dance_bot import SsFPattern1, SsSPattern1, waypoints
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLEDOn
from smacc_py.state_machines.sm_dance_bot.loop_pattern import LoopPattern, loop_end
from smacc_py.state_machines.sm_dance_bot.modestates import LoopingSuperstate, LoopStartState
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation


class SsTest(LoopingSuperstate):
    """A looping superstate outside any machine."""

    inner_initial_state = "StiTestStart"
    reactions = loop_end("StiTestStart", "StAfter")


PATTERN = LoopPattern(SsTest, __name__)
StiTestStart = PATTERN.loop_start("StiTestStart", "StiTestTurn", "Again, or done.")
StiTestTurn = PATTERN.motion("StiTestTurn", CbAbsoluteRotate, 90.0, led=CbLEDOff, following="StiTestDrive",
                             on_failure="StiTestStart", doc="Turn.")
StiTestDrive = PATTERN.forward("StiTestDrive", 0.5, led=CbLEDOn, following="StiTestStart", doc="Drive.")


def reactions(cls: type) -> list[tuple[str, str, str]]:
    return [(t.event.get_event_label(), t.target_name(), t.tag.__name__) for t in cls.reactions]


def test_the_superstate_leaves_on_loop_end_and_the_loop_start_continues_into_the_first_motion() -> None:
    assert reactions(SsTest) == [(EvLoopEnd["StiTestStart"].get_event_label(), "StAfter", ENDLOOP.__name__)]
    assert issubclass(StiTestStart, LoopStartState) and StiTestStart.superstate is SsTest
    assert reactions(StiTestStart) == [
        (EvLoopContinue["StiTestStart"].get_event_label(), "StiTestTurn", CONTINUELOOP.__name__)]
    assert StiTestStart.__doc__ == "Again, or done." and StiTestStart.parent_decl is SsTest


def test_a_motion_runs_its_behavior_and_led_and_goes_on_after_success_or_failure() -> None:
    rotate_ok = EvCbSuccess[CbAbsoluteRotate, OrNavigation]
    rotate_failed = EvCbFailure[CbAbsoluteRotate, OrNavigation]
    assert reactions(StiTestTurn) == [(rotate_ok.get_event_label(), "StiTestDrive", SUCCESS.__name__),
                                      (rotate_failed.get_event_label(), "StiTestStart", ABORT.__name__)]
    assert [(c.orthogonal, c.behavior, c.args) for c in StiTestTurn.behavior_configs] == [
        (OrNavigation, CbAbsoluteRotate, (90.0,)), (OrLED, CbLEDOff, ())]
    forward_failed = EvCbFailure[CbNavigateForward, OrNavigation]
    assert reactions(StiTestDrive)[1] == (forward_failed.get_event_label(), "StiTestStart", ABORT.__name__)
    assert StiTestDrive.behavior_configs[0].args == (0.5, waypoints.FORWARD_SPEED)
    assert (StiTestDrive.__module__, StiTestDrive.__qualname__) == (__name__, "StiTestDrive")


def test_the_patterns_keep_their_sizes_from_waypoints() -> None:
    from smacc_py.state_machines.sm_dance_bot import ss_f_pattern, ss_s_pattern

    assert ss_f_pattern.StiFPatternForward1.behavior_configs[0].args == (SsFPattern1.ray_length,
                                                                         waypoints.FORWARD_SPEED)
    assert ss_f_pattern.StiFPatternRotate1.behavior_configs[0].args == (SsFPattern1.direction.value,)
    assert ss_s_pattern.StiSPatternForward4.behavior_configs[0].args == (SsSPattern1.pitch2_length,
                                                                         waypoints.FORWARD_SPEED)
