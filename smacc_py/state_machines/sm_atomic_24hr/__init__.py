"""sm_atomic_24hr: SMACC2's endurance reference machine (smacc2_sm_reference_library/sm_atomic_24hr).

sm_atomic's shape, slowed down to run for a day: State1 ⇄ State2, each leaving on the
``EvTimer`` of a ``CbTimerCountdownOnce(500)`` counted on a ``ClRosTimer`` ticking every second, so a
state lasts 500 s of node clock and 24 h hold 172 transitions (7.2 an hour). It exists to show that a
long run keeps its memory and its pace: ``bench/bench_sm_atomic_24hr.py`` drives it through 24 h of
sim time as fast as it keeps up. Run it with ``smacc-run sm_atomic_24hr``.
"""

from smacc_py.state_machines.sm_atomic_24hr.sm_atomic_24hr import (
    NOMINAL_TRANSITIONS,
    STATE_SECONDS,
    SmAtomic24Hr,
)
from smacc_py.state_machines.sm_atomic_24hr.states import State1, State2

STATE_MACHINE = SmAtomic24Hr

__all__ = ["NOMINAL_TRANSITIONS", "STATE_MACHINE", "STATE_SECONDS", "SmAtomic24Hr", "State1", "State2"]
