"""The orthogonals of sm_three_some (upstream's ``orthogonals/``)."""

from smacc_py.state_machines.sm_three_some.orthogonals.or_keyboard import OrKeyboard
from smacc_py.state_machines.sm_three_some.orthogonals.or_subscriber import OrSubscriber
from smacc_py.state_machines.sm_three_some.orthogonals.or_timer import OrTimer

__all__ = ["OrKeyboard", "OrSubscriber", "OrTimer"]
