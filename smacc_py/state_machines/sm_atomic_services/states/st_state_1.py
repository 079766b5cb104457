"""``State1``: a countdown of 5 ticks whose EvTimer leads to State2 (SUCCESS)."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import SUCCESS, EvTimer, SmaccState, Transition
from smacc_py.state_machines.sm_atomic_services.orthogonals.or_timer import OrTimer

COUNTDOWN_TICKS = 5  # CbTimerCountdownOnce(5): one EvTimer after 5 client ticks


class State1(SmaccState, parent="SmAtomicServices"):
    """Five ticks, then State2."""

    reactions = [Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "State2", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)

    def on_entry(self) -> None:
        self.getLogger().info("On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info("On Exit!")
