"""``State1``: a loop countdown of 3 ticks (its events go unhandled, as upstream's) and a countdown of 5
ticks whose EvTimer leads to State2 (SUCCESS). The state names its machine by name, so this module
does not import the machine's."""

from __future__ import annotations

from smacc_py.clients.cl_ros2_timer import CbTimerCountdownLoop, CbTimerCountdownOnce
from smacc_py.core import SUCCESS, EvTimer, SmaccState, Transition
from smacc_py.state_machines.sm_atomic.orthogonals.or_timer import OrTimer

LOOP_TICKS = 3  # CbTimerCountdownLoop: an EvTimer every 3 client ticks
COUNTDOWN_TICKS = 5  # CbTimerCountdownOnce: one EvTimer after 5 client ticks


class State1(SmaccState, parent="SmAtomic"):
    """Five ticks, then State2."""

    reactions = [Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "State2", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownLoop, LOOP_TICKS)
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, COUNTDOWN_TICKS)

    def on_entry(self) -> None:
        self.getLogger().info("On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info("On Exit!")
