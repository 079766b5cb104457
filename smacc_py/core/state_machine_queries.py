"""``StateMachineQueries``: the read-only questions a running machine answers, split from dispatch.

``SmaccStateMachineBase`` (``state_machine.py``) owns the event queue and run-to-completion dispatch;
this mixin, which it inherits, holds only the lookups that states, behaviors, clients, the ROS runtime
and tests make against it: which states are active, whether it is initialised or running, which
orthogonal, client or component of a given type exists (``requires_*`` raise SmaccLookupError naming the
caller), named blackboard reads, and the introspection description. Nothing here posts events, takes the
machine's locks or changes its state, so dispatch logic can be read without these and vice versa.

The attributes it reads are created by ``SmaccStateMachineBase.__init__``; they are declared below so
the type checker knows them.
"""

from __future__ import annotations

from typing import Any, TypeVar

from smacc_py.core.client import ISmaccClient
from smacc_py.core.errors import missing
from smacc_py.core.global_data import MISSING, GlobalData
from smacc_py.core.introspection import StateMachineDescription, describe_model
from smacc_py.core.model import MachineModel
from smacc_py.core.orthogonal import Orthogonal
from smacc_py.core.state import SmaccState

C = TypeVar("C")


class StateMachineQueries:
    """Read-only state, orthogonal, client, component and blackboard lookups of a state machine
    (SMACC2: the lookups of ``smacc2::ISmaccStateMachine``: ``requiresComponent``, ``getGlobalSMData``)."""

    # Set by SmaccStateMachineBase.__init__ (and kept up to date by its dispatch).
    name: str
    model: MachineModel
    global_data: GlobalData
    _stack: list[SmaccState]
    _orthogonal_list: list[Orthogonal]
    _initialized: bool
    _running: bool

    @property
    def is_initialized(self) -> bool:
        """True once ``initialize()`` has run."""
        return self._initialized

    @property
    def is_running(self) -> bool:
        """True between ``start()`` and ``stop()``."""
        return self._running

    @property
    def current_state(self) -> SmaccState | None:
        """The innermost active state instance."""
        stack = self._stack
        return stack[-1] if stack else None

    def active_states(self) -> list[SmaccState]:
        """Active state instances, outermost first."""
        return list(self._stack)

    def current_state_names(self) -> list[str]:
        """Active state names outermost first (``SmaccStatus.current_states``)."""
        return [type(s).__name__ for s in self._stack]

    def _leaf_name(self) -> str:
        return type(self._stack[-1]).__name__ if self._stack else "<no state>"

    def get_orthogonal(self, orthogonal_type: type[C]) -> C:
        """The orthogonal of that type; SmaccLookupError when the machine did not create it."""
        for orthogonal in self._orthogonal_list:
            if type(orthogonal) is orthogonal_type:
                return orthogonal
        raise missing("orthogonal", orthogonal_type, self.name, "the machine")

    @property
    def orthogonals(self) -> list[Orthogonal]:
        """Orthogonals in creation order."""
        return list(self._orthogonal_list)

    def requires_client(self, client_type: type[C], who: str | None = None) -> C:
        """The first client of that type on any orthogonal; SmaccLookupError naming ``who`` when absent."""
        for orthogonal in self._orthogonal_list:
            found = orthogonal.get_client(client_type)
            if found is not None:
                return found
        raise missing("client", client_type, who or self.name, "any orthogonal")

    def requires_component(self, component_type: type[C], who: str | None = None) -> C:
        """The first component of that type on any client; SmaccLookupError naming ``who`` when absent."""
        for orthogonal in self._orthogonal_list:
            for client in orthogonal.clients:
                found = client.get_component(component_type)
                if found is not None:
                    return found
        raise missing("component", component_type, who or self.name, "any client")

    def clients(self) -> list[ISmaccClient]:
        """Every client, in orthogonal creation order."""
        return [c for o in self._orthogonal_list for c in o.clients]

    def get_global_sm_data(self, name: str, default: Any = MISSING) -> Any:
        """Read a named value; ``default`` when given and absent, else SmaccLookupError."""
        return self.global_data.get(name, default)

    def describe(self) -> StateMachineDescription:
        """Static description plus the client names of every orthogonal (after ``initialize()``)."""
        clients = {type(o).__name__: [c.client_type.__name__ for c in o.clients]
                   for o in self._orthogonal_list}
        return describe_model(self.model, self.name, clients)
