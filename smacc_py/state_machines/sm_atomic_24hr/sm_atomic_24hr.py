"""``SmAtomic24Hr``: ``SmaccStateMachineBase<SmAtomic24Hr, State1>`` with the orthogonal OrTimer
(upstream's ``sm_atomic_24hr.hpp``)."""

from __future__ import annotations

from smacc_py.core import SmaccStateMachineBase
from smacc_py.state_machines.sm_atomic_24hr.orthogonals.or_timer import TICK_S, OrTimer
from smacc_py.state_machines.sm_atomic_24hr.states import COUNTDOWN_TICKS, State1

#: Node-clock seconds each state lasts: its CbTimerCountdownOnce counts this many ticks of 1 s.
STATE_SECONDS = COUNTDOWN_TICKS * TICK_S
#: (source, target, tag) of the first transitions, as upstream's reactions give them.
NOMINAL_TRANSITIONS = (("State1", "State2", "SUCCESS"), ("State2", "State1", "SUCCESS")) * 2


class SmAtomic24Hr(SmaccStateMachineBase):
    """State1 ⇄ State2, one transition every STATE_SECONDS."""

    initial_state = State1

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTimer)
