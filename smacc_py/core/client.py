"""Clients and components: SM-lifetime proxies to the outside world (action, topic, timer ...).

A client is created by its orthogonal (``Orthogonal.on_initialize`` → ``create_client``) and lives as long
as the machine; it owns components (``client.create_component``), reusable pieces that behaviors fetch
with ``requires_component``. The core classes know nothing about ROS: the ROS layer subclasses them.
``on_initialize`` of every client, then of every component, runs after all orthogonals exist, so a
component may look up components of other clients.

This module sits below the orthogonal and the machine: a client reaches them through ``OrthogonalPort``
(declared here, implemented by ``Orthogonal``) and ``MachinePort``.
"""

from __future__ import annotations

from typing import Any, Protocol, TypeVar

from smacc_py.core.events import SmaccEvent
from smacc_py.core.ports import MachinePort, SmaccLogger

C = TypeVar("C")


class ISmaccClient:
    """Base of every client (``smacc2::ISmaccClient``). Subclasses override ``on_initialize`` and post
    events with ``post_event``."""

    orthogonal: OrthogonalPort
    sm: MachinePort
    components: list[ISmaccComponent]
    #: The type the orthogonal asked for: this class, or the one it stands in for (a substitute).
    client_type: type

    def _attach(self, orthogonal: OrthogonalPort, client_type: type | None = None) -> None:
        self.orthogonal = orthogonal
        self.sm = orthogonal.sm
        self.components = []
        self.client_type = client_type if client_type is not None else type(self)

    def on_initialize(self) -> None:
        """Called once after every orthogonal and client exists (create publishers, wire signals)."""

    def create_component(self, component_type: type[C], *args: Any, **kwargs: Any) -> C:
        """Construct a component owned by this client (or the machine's stand-in for ``component_type``);
        its ``on_initialize`` runs at machine init."""
        component = self.sm.build_part(component_type, args, kwargs)
        if not isinstance(component, ISmaccComponent):
            raise TypeError(f"{component_type.__name__} is not an ISmaccComponent")
        component._attach(self)
        self.components.append(component)
        if self.sm.is_initialized:
            component.on_initialize()
        return component

    def get_component(self, component_type: type[C]) -> C | None:
        """The first component of this client that is an instance of ``component_type``, or None."""
        for component in self.components:
            if isinstance(component, component_type):
                return component
        return None

    def own_event(self, template: type[SmaccEvent]) -> type[SmaccEvent]:
        """``template[ThisClient, ThisOrthogonal]``, the event SMACC2 clients post about themselves; a
        substitute posts it under the client type it stands in for, so transitions match unchanged."""
        return template[self.client_type, type(self.orthogonal)]

    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post an event with ABSOLUTE lifetime (clients outlive states)."""
        self.sm.post_event(event)

    def get_logger(self) -> SmaccLogger:
        """The machine's logger (the node's under the ROS runtime), as SMACC2's ``getLogger()``."""
        return self.sm.get_logger()

    getLogger = get_logger  # SMACC2's spelling


class ISmaccComponent:
    """Base of every component (``smacc2::ISmaccComponent``); owned by one client."""

    owner: ISmaccClient
    sm: MachinePort

    def _attach(self, owner: ISmaccClient) -> None:
        self.owner = owner
        self.sm = owner.sm

    def on_initialize(self) -> None:
        """Called once after all clients are initialised."""

    def requires_component(self, component_type: type[C]) -> C:
        """A component of the same client first, then of any client; SmaccLookupError when absent."""
        found = self.owner.get_component(component_type)
        if found is not None:
            return found
        return self.sm.requires_component(component_type, who=type(self).__name__)

    def requires_client(self, client_type: type[C]) -> C:
        """A client of any orthogonal; SmaccLookupError when absent."""
        return self.sm.requires_client(client_type, who=type(self).__name__)

    def create_sibling_component(self, component_type: type[C], *args: Any, **kwargs: Any) -> C:
        """Create another component on the same client."""
        return self.owner.create_component(component_type, *args, **kwargs)

    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post an event with ABSOLUTE lifetime."""
        self.sm.post_event(event)

    def get_logger(self) -> SmaccLogger:
        """The machine's logger (the node's under the ROS runtime), as SMACC2's ``getLogger()``."""
        return self.sm.get_logger()

    getLogger = get_logger  # SMACC2's spelling


class OrthogonalPort(Protocol):
    """What clients and behaviors ask of the orthogonal that holds them (``smacc2::ISmaccOrthogonal``);
    ``Orthogonal`` implements it."""

    @property
    def sm(self) -> MachinePort:
        """The machine the orthogonal belongs to."""

    @property
    def clients(self) -> list[ISmaccClient]:
        """The orthogonal's clients, in creation order."""

    def get_client(self, client_type: type[C]) -> C | None:
        """The first client that is an instance of ``client_type``, or None."""
