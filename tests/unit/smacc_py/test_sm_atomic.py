"""sm_atomic against upstream's definition (sm_atomic/include/sm_atomic/states/*.hpp), on the manual
clock: State1 → State2 → State1 ... on EvTimer[CbTimerCountdownOnce, OrTimer], every 5 ticks of the 1 s
ClRos2Timer; State1's CbTimerCountdownLoop(3) posts EvTimer every 3 ticks, which nothing handles."""

from __future__ import annotations

from typing import Any

from smacc_py.core import EvTimer, SmaccObserver
from smacc_py.state_machines.sm_atomic import NOMINAL_TRANSITIONS, STATE_SECONDS, SmAtomic
from smacc_py.testing import MachineHarness


class Timers(SmaccObserver):
    def __init__(self) -> None:
        self.loop_at: list[float] = []

    def on_event_posted(self, sm: Any, event: Any) -> None:
        if isinstance(event, EvTimer) and type(event).__name__ == "EvTimer[CbTimerCountdownLoop, OrTimer]":
            self.loop_at.append(round(sm.now(), 6))


def test_the_states_alternate_every_five_ticks_of_the_one_second_timer() -> None:
    harness = MachineHarness(SmAtomic)
    timers = Timers()
    harness.sm.add_observer(timers)
    with harness:
        harness.advance(4 * STATE_SECONDS + 0.5)
        assert tuple(harness.transitions()) == NOMINAL_TRANSITIONS
        assert [record.stamp_s for record in harness.sm.transition_log] == [5.0, 10.0, 15.0, 20.0]
        assert STATE_SECONDS == 5.0
        # State1 runs 0-5 s and 10-15 s; its loop countdown fires at its 3rd tick in each visit
        assert timers.loop_at == [3.0, 13.0]
