"""``State1``: a countdown of 500 ticks whose EvTimer leads to State2 (SUCCESS). The state names its
machine by name, so this module does not import the machine's."""

from __future__ import annotations

from smacc_py.clients.cl_ros_timer import CbTimerCountdownOnce
from smacc_py.core import SUCCESS, EvTimer, SmaccState, Transition
from smacc_py.state_machines.sm_atomic_24hr.orthogonals.or_timer import OrTimer

COUNTDOWN_TICKS = 500  # CbTimerCountdownOnce: one EvTimer after 500 client ticks


class State1(SmaccState, parent="SmAtomic24Hr"):
    """500 ticks, then State2."""

    reactions = [Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "State2", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)

    def on_entry(self) -> None:
        self.getLogger().info("On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info("On Exit!")
