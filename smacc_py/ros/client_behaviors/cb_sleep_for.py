"""``CbSleepFor``: EvCbSuccess after a duration of machine clock (SMACC2's CbSleepFor).

SMACC2's version sleeps in its own thread; this one is polled (ISmaccUpdatable) on the node clock, so
under ``use_sim_time`` a 5 s sleep is 5 s of simulated time, and leaving the state early costs
nothing. The success comes at the first poll at or after the deadline (at most 1 /
signal_detector_loop_freq s late).
"""

from __future__ import annotations

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import check_duration


class CbSleepFor(CbOutcomeBase):
    """Posts ``EvCbSuccess[CbSleepFor, Or](slept_s=...)`` once ``duration_s`` s have passed."""

    def __init__(self, duration_s: float) -> None:
        self.duration_s = check_duration("CbSleepFor", "duration_s", duration_s)

    def start(self) -> None:
        self.poll()

    def poll(self) -> None:
        slept = self.sm.now() - self.started_s
        if slept >= self.duration_s:
            self.finish(True, slept_s=slept)
