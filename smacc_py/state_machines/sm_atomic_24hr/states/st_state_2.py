"""``State2``: a countdown of 500 ticks whose EvTimer leads back to State1 (SUCCESS)."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import SUCCESS, EvTimer, SmaccState, Transition
from smacc_py.state_machines.sm_atomic_24hr.orthogonals.or_timer import OrTimer
from smacc_py.state_machines.sm_atomic_24hr.states.st_state_1 import COUNTDOWN_TICKS


class State2(SmaccState, parent="SmAtomic24Hr"):
    """500 ticks, then State1."""

    reactions = [Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "State1", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)

    def runtime_configure(self) -> None:
        self.getLogger().info("Entering State2")

    def on_entry(self) -> None:
        self.getLogger().info("On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info("On Exit!")
