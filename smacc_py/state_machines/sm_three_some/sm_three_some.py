"""``SmThreeSome``: ``SmaccStateMachineBase<SmThreeSome, MsRun>`` with OrTimer, OrKeyboard and
OrSubscriber (upstream's ``sm_three_some.hpp``), and the transitions it takes without input."""

from __future__ import annotations

from smacc_py.core import SmaccStateMachineBase

# Imported for their effect, declaring the states: each names its parent by name, so none imports this one.
from smacc_py.state_machines.sm_three_some import mode_states, states, superstates  # noqa: F401
from smacc_py.state_machines.sm_three_some.events import EvFail, EvToDeep
from smacc_py.state_machines.sm_three_some.orthogonals import OrKeyboard, OrSubscriber, OrTimer
from smacc_py.state_machines.sm_three_some.orthogonals.or_timer import TICK_S

LOOP_ITERATIONS = 5  # Ss1/Ss2 ``total_iterations()``


def _loop(superstate: str) -> list[tuple[str, str, str]]:
    """A superstate's five iterations (StiState1 → 2 on CONTINUELOOP, 2 → 3 → 1 on TIMEOUT)."""
    one = [(f"{superstate}StiState1", f"{superstate}StiState2", "CONTINUELOOP"),
           (f"{superstate}StiState2", f"{superstate}StiState3", "TIMEOUT"),
           (f"{superstate}StiState3", f"{superstate}StiState1", "TIMEOUT")]
    return one * LOOP_ITERATIONS


#: (source, target, tag) of every transition without input, timers only, as upstream's reactions give
#: them (a transition without a tag takes its event's default: EvLoopEnd's is ENDLOOP, as in SMACC2):
#: 35 transitions in 115 s of node clock, ending in StState4.
NOMINAL_TRANSITIONS: tuple[tuple[str, str, str], ...] = (
    ("StState1", "StState2", "TIMEOUT"),
    ("StState2", "StState3", "TIMEOUT"),
    ("StState3", "Ss1", "TIMEOUT"),
    *_loop("Ss1"),
    ("Ss1", "Ss2", "ENDLOOP"),
    *_loop("Ss2"),
    ("Ss2", "StState4", "ENDLOOP"),
)


class SmThreeSome(SmaccStateMachineBase):
    """Run mode with four states and two looping superstates; a recovery mode nobody enters."""

    initial_state = "MsRun"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTimer)
        self.create_orthogonal(OrKeyboard)
        self.create_orthogonal(OrSubscriber)


__all__ = ["LOOP_ITERATIONS", "NOMINAL_TRANSITIONS", "TICK_S", "EvFail", "EvToDeep", "SmThreeSome"]
