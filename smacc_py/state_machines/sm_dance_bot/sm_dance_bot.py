"""``SmDanceBot``: SMACC2's reference navigation machine (sm_dance_bot.hpp).

Initial state MsDanceBotRunMode (→ StAcquireSensors); eight orthogonals created in upstream's order;
the global data ``counter_1`` and ``rt_ready_flag`` that upstream declares are kept. The states name
this class as their parent (``parent=SmDanceBot``), so they import it, and the initial state is given
by name; the package's ``__init__`` imports every state module, so import the machine from the package.
"""

from __future__ import annotations

from smacc_py.core import SmaccStateMachineBase
from smacc_py.state_machines.sm_dance_bot.orthogonals import ORTHOGONALS


class SmDanceBot(SmaccStateMachineBase):
    """Acquire sensors, count down, then dance radial, F and S patterns between waypoints; an
    over-temperature pauses the dance in the recovery mode, which resumes it (deep history)."""

    initial_state = "MsDanceBotRunMode"

    def on_initialize(self) -> None:
        self.set_global_sm_data("counter_1", 0)
        self.set_global_sm_data("rt_ready_flag", False)
        for orthogonal in ORTHOGONALS:
            self.create_orthogonal(orthogonal)
