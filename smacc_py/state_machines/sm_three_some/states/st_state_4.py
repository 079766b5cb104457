"""``StState4``: the end. Upstream declares its one transition (EvTimer → Ss1, TIMEOUT) in a typedef
named ``transitions``, which SMACC2 does not read (it reads ``reactions``), so the state never leaves;
this port keeps that behaviour: a countdown whose EvTimer nobody handles."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.state_machines.sm_three_some.orthogonals import OrTimer
from smacc_py.state_machines.sm_three_some.states.common import COUNTDOWN_TICKS, LoggedState


class StState4(LoggedState, parent="MsRun"):
    """The last state: a countdown, and no reactions."""

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)
