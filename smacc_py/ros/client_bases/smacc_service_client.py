"""``SmaccServiceClient``: the base of clients that call one ROS service.

SMACC2's ``smacc2::client_bases::SmaccServiceClient<ServiceType>``, without its blocking call: here
``call(request)`` returns a ``ServiceCall`` at once and the answer comes back as an event,
``EvServiceResponse[YourClient, Or](response=..., service=...)``, or, when the server is not
discovered or does not answer within ``timeout_s`` s of machine clock,
``EvServiceFailure[YourClient, Or](reason=..., service=...)``::

    class ClResetOdom(SmaccServiceClient):
        def __init__(self) -> None:
            super().__init__(Empty, "/reset_odom")

    Transition(EvServiceResponse[ClResetOdom, OrOdom], StDriving)

The work is done by a ``CpServiceClient`` created in ``on_initialize``; a subclass that overrides
``on_initialize`` must call ``super().on_initialize()``.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient
from smacc_py.ros.components.checks import check_created, check_name, check_service_type
from smacc_py.ros.components.cp_service_client import DEFAULT_SERVICE_TIMEOUT_S, CpServiceClient
from smacc_py.ros.components.service_call import FailureCallback, ResponseCallback, ServiceCall


class SmaccServiceClient(ISmaccClient):
    """Client of service ``service_name`` of type ``srv_type`` (e.g. std_srvs.srv.Trigger)."""

    def __init__(self, srv_type: Any, service_name: str) -> None:
        label = f"{type(self).__name__}({service_name!r})"
        self.srv_type = check_service_type(label, srv_type)
        self.service_name = check_name(label, "service", service_name)
        self._service: CpServiceClient | None = None

    def on_initialize(self) -> None:
        """Create the service client component."""
        self._service = self.create_component(CpServiceClient, self.srv_type, self.service_name)

    @property
    def service(self) -> CpServiceClient:
        """The component doing the work (SmaccError if ``super().on_initialize()`` was never called)."""
        return check_created(type(self).__name__, self._service, "CpServiceClient")

    def service_ready(self) -> bool:
        """True once the server is discovered."""
        return self.service.service_ready()

    def call(self, request: Any | None = None, *, timeout_s: float = DEFAULT_SERVICE_TIMEOUT_S,
             on_response: ResponseCallback | None = None,
             on_failure: FailureCallback | None = None) -> ServiceCall:
        """Send ``request`` (default: an empty ``srv_type.Request()``); never blocks."""
        if request is None:
            request = self.srv_type.Request()
        return self.service.call(request, timeout_s=timeout_s, on_response=on_response, on_failure=on_failure)
