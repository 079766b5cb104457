"""``CpServiceClient``: one service client owned by a client (SMACC2 Jazzy's CpServiceClient).

``call(request)`` returns at once with a ``ServiceCall``. Its answer is posted as
``EvServiceResponse[Client, Or](response=..., service=...)``, and a failure (server not discovered or
no answer within ``timeout_s`` s of machine clock) as ``EvServiceFailure[Client, Or](reason=...,
service=...)``, where Client is the owning client's type; ``on_response`` / ``on_failure`` given to
``call`` run after the event is posted. Calls run concurrently; deadlines are checked in the runtime's
ISmaccUpdatable polling. An abandoned call (``ServiceCall.abandon``) posts nothing.
"""

from __future__ import annotations

import threading
from typing import Any

from smacc_py.core import EvServiceFailure, EvServiceResponse, ISmaccComponent, ISmaccUpdatable, SmaccError
from smacc_py.ros.components.checks import check_duration, check_instance, check_name, check_service_type
from smacc_py.ros.components.service_call import FailureCallback, ResponseCallback, ServiceCall
from smacc_py.ros.context import ros_context

DEFAULT_SERVICE_TIMEOUT_S = 10.0  # s of machine clock from call() to the answer, discovery included


class CpServiceClient(ISmaccComponent, ISmaccUpdatable):
    """Client of service ``service_name`` of type ``srv_type`` (e.g. std_srvs.srv.Trigger)."""

    def __init__(self, srv_type: Any, service_name: str) -> None:
        self.label = f"CpServiceClient({service_name!r})"
        self.srv_type = check_service_type(self.label, srv_type)
        self.service_name = check_name(self.label, "service", service_name)
        self._client: Any = None
        self._calls: list[ServiceCall] = []
        self._lock = threading.Lock()

    def on_initialize(self) -> None:
        self._client = ros_context(self.sm).node.create_client(self.srv_type, self.service_name)

    def service_ready(self) -> bool:
        """True once the service server is discovered."""
        return self._client is not None and bool(self._client.service_is_ready())

    def call(self, request: Any, *, timeout_s: float = DEFAULT_SERVICE_TIMEOUT_S,
             on_response: ResponseCallback | None = None,
             on_failure: FailureCallback | None = None) -> ServiceCall:
        """Send ``request`` (a ``srv_type.Request``) as soon as the server is seen; never blocks."""
        check_instance(self.label, "the request", request, self.srv_type.Request)
        timeout = check_duration(self.label, "timeout_s", timeout_s)
        if self._client is None:
            raise SmaccError(f"{self.label}: call() before the machine was initialized")

        def answered(response: Any) -> None:
            self.post_event(self.owner.own_event(EvServiceResponse)(response=response,
                                                                    service=self.service_name))
            if on_response is not None:
                on_response(response)

        def failed(reason: str) -> None:
            self.post_event(self.owner.own_event(EvServiceFailure)(reason=reason, service=self.service_name))
            if on_failure is not None:
                on_failure(reason)

        call = ServiceCall(self._client, request, timeout_s=timeout, on_response=answered,
                           on_failure=failed, service_name=self.service_name)
        with self._lock:
            self._calls = [c for c in self._calls if not c.done] + [call]
        call.start(self.sm.now())
        return call

    def update(self) -> None:
        """Send calls whose server appeared, fail those past their deadline."""
        with self._lock:
            calls = [c for c in self._calls if not c.done]
            self._calls = calls
        now = self.sm.now()
        for call in calls:
            call.poll(now)
