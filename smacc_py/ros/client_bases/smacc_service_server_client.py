"""``SmaccServiceServerClient``: the base of clients that serve one ROS service.

SMACC2's ``smacc2::client_bases::SmaccServiceServerClient<ServiceType>``. Override ``on_request`` (or
pass ``handler``) to fill the response; it runs on the executor thread and must return quickly. After
each request ``EvServiceRequestReceived[YourClient, Or](request=..., response=..., service=...)`` is
posted, so that a state can move on when it is called::

    class ClStartButton(SmaccServiceServerClient):
        def __init__(self) -> None:
            super().__init__(Trigger, "/start_mission")

        def on_request(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
            response.success = True
            return response

The server is a ``CpServiceServer`` created in ``on_initialize``; a subclass that overrides
``on_initialize`` must call ``super().on_initialize()``.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient
from smacc_py.ros.components.checks import check_name, check_service_type
from smacc_py.ros.components.cp_service_server import CpServiceServer, EvServiceRequestReceived, Handler

__all__ = ["EvServiceRequestReceived", "SmaccServiceServerClient"]


class SmaccServiceServerClient(ISmaccClient):
    """Server of ``service_name`` (``srv_type``); ``handler(request, response) -> response`` or
    ``on_request`` answers."""

    def __init__(self, srv_type: Any, service_name: str, handler: Handler | None = None) -> None:
        label = f"{type(self).__name__}({service_name!r})"
        self.srv_type = check_service_type(label, srv_type)
        self.service_name = check_name(label, "service", service_name)
        if handler is not None and not callable(handler):
            raise TypeError(f"{label}: handler must be callable(request, response) -> response, got "
                            f"{handler!r}")
        self._handler = handler
        self.server: CpServiceServer | None = None

    def on_initialize(self) -> None:
        """Create the service server component."""
        handler = self._handler if self._handler is not None else self.on_request
        self.server = self.create_component(CpServiceServer, self.srv_type, self.service_name, handler)

    def on_request(self, request: Any, response: Any) -> Any:
        """Fill and return ``response`` (default: leave it as constructed)."""
        return response
