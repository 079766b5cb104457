"""``MachineAssembly``: building a machine's parts (orthogonals, clients, components), split from dispatch.

``SmaccStateMachineBase`` inherits this mixin. The user's ``on_initialize`` creates the orthogonals; each
orthogonal's ``on_initialize`` creates its clients, which create their components; ``initialize()`` then
runs every client's and after that every component's ``on_initialize`` (so a component may look up
components of other clients) and checks that each orthogonal a state configures was created and that
each configured behavior can work on it (``ISmaccClientBehavior.configuration_problem``). All of it
happens once, before the first state is entered, which is why it lives apart from the event queue and
the transitions in ``state_machine.py``.

Substitutes. ``SmaccStateMachineBase(substitutes={ClNav2Z: make_scripted_client})`` makes every
``create_client(ClNav2Z, ...)`` (and every ``create_component`` of a substituted component type) call the
stand-in factory with the same arguments instead. States, orthogonals, tags and behaviors then run
exactly as shipped while the stand-in replaces the I/O: this is how a machine written for ROS runs in a
unit test on scripted fakes, without test-only branches in its states (SMACC2, whose types are fixed at
C++ compile time, has no equivalent). A stand-in must be an instance of the type it replaces, so
``requires_client(ClNav2Z)`` keeps finding it, and a client stand-in posts its events under the replaced
type (``EvActionSucceeded[ClNav2Z, Or]``), so the machine's transitions match as in production.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, TypeVar

from smacc_py.core.client import ISmaccClient, ISmaccComponent
from smacc_py.core.errors import InvalidDefinitionError
from smacc_py.core.model import MachineModel
from smacc_py.core.orthogonal import Orthogonal

C = TypeVar("C")
#: Builds a stand-in from the arguments the orthogonal or client passed for the replaced type.
StandInFactory = Callable[..., object]


def check_substitutes(substitutes: Mapping[type, StandInFactory] | None) -> dict[type, StandInFactory]:
    """The substitutes as a dict; InvalidDefinitionError naming a key that is not a client or component
    class, or a stand-in that cannot be called."""
    checked: dict[type, StandInFactory] = {}
    for wanted, stand_in in (substitutes or {}).items():
        if not (isinstance(wanted, type) and issubclass(wanted, (ISmaccClient, ISmaccComponent))):
            raise InvalidDefinitionError(f"substitutes: {wanted!r} is not an ISmaccClient or ISmaccComponent "
                                         "class")
        if not callable(stand_in):
            raise InvalidDefinitionError(f"substitutes: the stand-in for {wanted.__name__} is not callable: "
                                         f"{stand_in!r}")
        checked[wanted] = stand_in
    return checked


class MachineAssembly:
    """Creation of orthogonals, clients and components, and the checks that run before the first state
    (SMACC2: ``ISmaccStateMachine::createOrthogonal`` and the orthogonals' ``initialize``)."""

    # Set by SmaccStateMachineBase.__init__.
    name: str
    model: MachineModel
    substitutes: dict[type, StandInFactory]
    _orthogonals: dict[type[Orthogonal], Orthogonal]
    _orthogonal_list: list[Orthogonal]
    _initialized: bool

    def on_initialize(self) -> None:
        """Create the orthogonals (``create_orthogonal``); runs once, before any state is entered."""

    def create_orthogonal(self, orthogonal_type: type[C]) -> C:
        """Create an orthogonal and run its ``on_initialize`` (which creates its clients)."""
        if not (isinstance(orthogonal_type, type) and issubclass(orthogonal_type, Orthogonal)):
            raise InvalidDefinitionError(f"{self.name}.create_orthogonal: {orthogonal_type!r} is not an "
                                         f"Orthogonal")
        if orthogonal_type in self._orthogonals:
            raise InvalidDefinitionError(f"{self.name}: orthogonal {orthogonal_type.__name__} created twice")
        orthogonal = orthogonal_type()
        orthogonal._attach(self)  # type: ignore[arg-type]  # the mixin is only used by the machine
        self._orthogonals[orthogonal_type] = orthogonal
        self._orthogonal_list.append(orthogonal)
        orthogonal.on_initialize()
        return orthogonal

    def build_part(self, wanted: type[C], args: tuple[Any, ...], kwargs: Mapping[str, Any]) -> C:
        """``wanted(*args, **kwargs)``, or its substitute built with the same arguments (see the module
        docstring); InvalidDefinitionError when the substitute does not build a ``wanted``."""
        factory = self.substitutes.get(wanted)
        if factory is None:
            return wanted(*args, **kwargs)
        part = factory(*args, **kwargs)
        if not isinstance(part, wanted):
            raise InvalidDefinitionError(
                f"{self.name}: the substitute for {wanted.__name__} built a {type(part).__name__}, which is "
                f"not a {wanted.__name__} (stand-ins must subclass the type they replace)"
            )
        return part

    def initialize(self) -> None:
        """Create orthogonals, clients and components and check that every configured orthogonal exists."""
        if self._initialized:
            return
        self.on_initialize()
        for orthogonal in self._orthogonal_list:
            for client in orthogonal.clients:
                client.on_initialize()
        for orthogonal in self._orthogonal_list:
            for client in orthogonal.clients:
                for component in client.components:
                    component.on_initialize()
        for orthogonal_type, users in self.model.configured_orthogonals().items():
            if orthogonal_type not in self._orthogonals:
                state, behavior = users[0]
                created = ", ".join(t.__name__ for t in self._orthogonals) or "none"
                raise InvalidDefinitionError(
                    f"{state.__name__} configures {behavior.__name__} on {orthogonal_type.__name__}, but "
                    f"{self.name}.on_initialize does not create {orthogonal_type.__name__} (created: "
                    f"{created})"
                )
        for state in self.model.states:
            for cfg in state.behavior_configs:
                problem = cfg.behavior.configuration_problem(self._orthogonals[cfg.orthogonal], cfg.args,
                                                             cfg.kwargs)
                if problem:
                    raise InvalidDefinitionError(f"{state.__name__}: {cfg.behavior.__name__} on "
                                                 f"{cfg.orthogonal.__name__}: {problem}")
        self._initialized = True
