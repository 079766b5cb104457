"""The simple states of sm_three_some (upstream's ``states/st_state_*.hpp``) and their common setup."""

from smacc_py.state_machines.sm_three_some.states.st_state_1 import StState1
from smacc_py.state_machines.sm_three_some.states.st_state_2 import StState2
from smacc_py.state_machines.sm_three_some.states.st_state_3 import StState3
from smacc_py.state_machines.sm_three_some.states.st_state_4 import StState4

__all__ = ["StState1", "StState2", "StState3", "StState4"]
