"""The two states of sm_atomic_24hr (upstream's ``states/st_state_1.hpp`` and ``st_state_2.hpp``)."""

from smacc_py.state_machines.sm_atomic_24hr.states.st_state_1 import COUNTDOWN_TICKS, State1
from smacc_py.state_machines.sm_atomic_24hr.states.st_state_2 import State2

__all__ = ["COUNTDOWN_TICKS", "State1", "State2"]
