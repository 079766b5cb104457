"""``CbServiceServer``: while its state is active, each call of the orthogonal's ClServiceServer is
posted as ``EvServiceRequestReceived[CbServiceServer, Or]`` (upstream's ``EvServiceRequestReceieved``,
from its ``CbServiceServerCallbackBase<Empty>``)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.clients import EvServiceRequestReceived
from smacc_py.core import SmaccClientBehavior
from smacc_py.state_machines.sm_atomic_services.clients import ClServiceServer


class CbServiceServer(SmaccClientBehavior):
    """Turns the server's requests into this behavior's events, for as long as the state lasts."""

    def on_entry(self) -> None:
        server = self.requires_client(ClServiceServer)
        self.service = server.service_name
        self._disconnect: Callable[[], None] = server.request_received.connect(self._on_request)

    def _on_request(self, request: Any) -> None:
        self.getLogger().info("CbServiceServer: service request received")
        self.post_event(self.own_event(EvServiceRequestReceived)(request=request, service=self.service))

    def on_exit(self) -> None:
        self._disconnect()


__all__ = ["CbServiceServer"]
