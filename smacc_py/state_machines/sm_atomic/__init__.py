"""sm_atomic: SMACC2's smallest reference machine (smacc2_sm_reference_library/sm_atomic) on smacc_py.

State1 ⇄ State2 on a 1 s ClRos2Timer: State1 runs CbTimerCountdownLoop(3) and CbTimerCountdownOnce(5)
and leaves on the countdown's EvTimer after 5 ticks; State2 runs CbTimerCountdownOnce(5) and goes
back. Counts are ticks of the client, as in C++, so each state lasts 5 s of node clock. The layout is
upstream's (the machine, ``orthogonals/``, ``states/``) and the states name their parents by name, as
``smacc-new`` writes them. Run it with ``smacc-run sm_atomic``.
"""

from smacc_py.state_machines.sm_atomic.sm_atomic import (
    NOMINAL_TRANSITIONS,
    STATE_SECONDS,
    SmAtomic,
)
from smacc_py.state_machines.sm_atomic.states import State1, State2

STATE_MACHINE = SmAtomic

__all__ = ["NOMINAL_TRANSITIONS", "STATE_MACHINE", "STATE_SECONDS", "SmAtomic", "State1", "State2"]
