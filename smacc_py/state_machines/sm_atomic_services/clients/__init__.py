"""The clients of sm_atomic_services (upstream's ``clients/``): both speak std_srvs/Empty.

* ``ClServiceServer``: a ``SmaccServiceServerClient<Empty>`` that also tells the behaviors connected to
  ``request_received`` of each call (SMACC2's ``onServiceRequestReceived`` signal, which its
  ``CbServiceServerCallbackBase`` connects to);
* ``ClServiceClient``: a ``SmaccServiceClient<Empty>``.
"""

from __future__ import annotations

from typing import Any

from std_srvs.srv import Empty

from smacc_py.clients import SmaccServiceClient, SmaccServiceServerClient, SmaccSignal


class ClServiceServer(SmaccServiceServerClient):
    """Serves ``service_name`` (std_srvs/Empty); each request is emitted on ``request_received``."""

    def __init__(self, service_name: str) -> None:
        super().__init__(Empty, service_name)
        self.request_received: SmaccSignal[Any] = SmaccSignal(f"ClServiceServer({service_name!r})"
                                                              ".request_received")

    def on_request(self, request: Any, response: Any) -> Any:
        self.request_received.emit(request)
        return response


class ClServiceClient(SmaccServiceClient):
    """Calls ``service_name`` (std_srvs/Empty)."""

    def __init__(self, service_name: str) -> None:
        super().__init__(Empty, service_name)


__all__ = ["ClServiceClient", "ClServiceServer"]
