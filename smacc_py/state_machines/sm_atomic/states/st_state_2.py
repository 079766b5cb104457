"""``State2``: a countdown of 5 ticks whose EvTimer leads back to State1 (SUCCESS)."""

from __future__ import annotations

from smacc_py.clients.cl_ros2_timer import CbTimerCountdownOnce
from smacc_py.core import SUCCESS, EvTimer, SmaccState, Transition
from smacc_py.state_machines.sm_atomic.orthogonals.or_timer import OrTimer
from smacc_py.state_machines.sm_atomic.states.st_state_1 import COUNTDOWN_TICKS


class State2(SmaccState, parent="SmAtomic"):
    """Five ticks, then State1."""

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
