"""The looping superstates of sm_three_some (upstream's ``superstates/``) and their inner states."""

from smacc_py.state_machines.sm_three_some.superstates.ss_superstate_1 import Ss1
from smacc_py.state_machines.sm_three_some.superstates.ss_superstate_2 import Ss2

__all__ = ["Ss1", "Ss2"]
