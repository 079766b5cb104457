"""The mode states of sm_three_some (upstream's ``mode_states/``)."""

from smacc_py.state_machines.sm_three_some.mode_states.ms_recover import MsRecover
from smacc_py.state_machines.sm_three_some.mode_states.ms_run import MsRun

__all__ = ["MsRecover", "MsRun"]
