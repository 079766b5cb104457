"""Orthogonals: SM-lifetime slots that hold clients and the behaviors of the active states.

SMACC2 orthogonals are concurrent *behavior slots*, not Harel parallel regions (SMACC2 #531): each keeps
a stack with one list of behaviors per active state level, so a superstate's behaviors stay alive while
its inner states run. ``on_initialize`` creates the clients (``create_client``). An orthogonal implements
the ``OrthogonalPort`` its clients and behaviors use, and reaches its machine through ``MachinePort``.
"""

from __future__ import annotations

from typing import Any, TypeVar

from smacc_py.core.client import ISmaccClient
from smacc_py.core.client_behavior import ISmaccClientBehavior
from smacc_py.core.ports import MachinePort

C = TypeVar("C")


class Orthogonal:
    """Base of every orthogonal (``smacc2::Orthogonal<T>``); override ``on_initialize`` to create clients."""

    sm: MachinePort
    clients: list[ISmaccClient]
    behavior_stack: list[list[ISmaccClientBehavior]]

    def _attach(self, sm: MachinePort) -> None:
        self.sm = sm
        self.clients = []
        self.behavior_stack = []

    def on_initialize(self) -> None:
        """Create this orthogonal's clients with ``create_client``."""

    def create_client(self, client_type: type[C], *args: Any, **kwargs: Any) -> C:
        """Construct a client owned by this orthogonal (SMACC2 ``createClient<ClX>(args)``), or the stand-in
        the machine was given for ``client_type`` (``SmaccStateMachineBase(substitutes=...)``)."""
        client = self.sm.build_part(client_type, args, kwargs)
        if not isinstance(client, ISmaccClient):
            raise TypeError(
                f"{type(self).__name__}.create_client: {client_type.__name__} is not an ISmaccClient"
            )
        client._attach(self, client_type)
        self.clients.append(client)
        return client

    def get_client(self, client_type: type[C]) -> C | None:
        """The first client that is an instance of ``client_type``, or None."""
        for client in self.clients:
            if isinstance(client, client_type):
                return client
        return None

    def get_client_behaviors(self) -> list[ISmaccClientBehavior]:
        """Behaviors of every active state on this orthogonal, outermost state first."""
        return [behavior for level in self.behavior_stack for behavior in level]
