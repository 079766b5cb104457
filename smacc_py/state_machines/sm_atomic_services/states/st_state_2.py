"""``State2``: waits for a call of the machine's service; its event leads back to State1 (SUCCESS)."""

from __future__ import annotations

from smacc_py.clients import EvServiceRequestReceived
from smacc_py.core import SUCCESS, SmaccState, Transition
from smacc_py.state_machines.sm_atomic_services.clients.client_behaviors import CbServiceServer
from smacc_py.state_machines.sm_atomic_services.orthogonals.or_services import OrServices


class State2(SmaccState, parent="SmAtomicServices"):
    """A service call, then State1."""

    reactions = [Transition(EvServiceRequestReceived[CbServiceServer, OrServices], "State1", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrServices, CbServiceServer)

    def runtime_configure(self) -> None:
        self.getLogger().info("Entering State2")

    def on_entry(self) -> None:
        self.getLogger().info("On Entry!")

    def on_exit(self) -> None:
        self.getLogger().info("On Exit!")
