"""``SmAtomicServices``: ``SmaccStateMachineBase<SmAtomicServices, State1>`` with OrTimer and OrServices
(upstream's ``sm_atomic_services.hpp``)."""

from __future__ import annotations

from smacc_py.core import SmaccStateMachineBase
from smacc_py.state_machines.sm_atomic_services.orthogonals.or_services import SERVICE, OrServices
from smacc_py.state_machines.sm_atomic_services.orthogonals.or_timer import OrTimer
from smacc_py.state_machines.sm_atomic_services.states import State1

#: (source, target, tag) of the first transitions when ``SERVICE`` is called once in each State2.
NOMINAL_TRANSITIONS = (("State1", "State2", "SUCCESS"), ("State2", "State1", "SUCCESS")) * 2


class SmAtomicServices(SmaccStateMachineBase):
    """State1 (a 5-tick countdown) ⇄ State2 (waits for a service call)."""

    initial_state = State1

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTimer)
        self.create_orthogonal(OrServices)


__all__ = ["NOMINAL_TRANSITIONS", "SERVICE", "SmAtomicServices"]
