"""``CbCallService``: call a service on state entry; EvCbSuccess with the response, else EvCbFailure.

SMACC2's ``CbServiceCall<ServiceType>(serviceName, request)``, without its blocking ``.get()``: the
behavior creates its own service client on entry, sends the request as soon as the server is
discovered, and posts ``EvCbSuccess[CbCallService, Or](response=...)`` when the answer comes (on the
executor thread), or ``EvCbFailure[CbCallService, Or](reason=...)`` when the server was not
discovered or did not answer within ``timeout_s`` s of machine clock. ``is_success(response)``, when
given, turns an answer it rejects (``Trigger``'s ``success == False``, say) into a failure. On state
exit the call is abandoned and the client destroyed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import check_duration, check_instance, check_name, check_service_type
from smacc_py.ros.components.cp_service_client import DEFAULT_SERVICE_TIMEOUT_S
from smacc_py.ros.components.service_call import ServiceCall
from smacc_py.ros.context import ros_context


class CbCallService(CbOutcomeBase):
    """Calls ``service_name`` (``srv_type``) with ``request`` (default: an empty request)."""

    def __init__(self, srv_type: Any, service_name: str, request: Any | None = None,
                 timeout_s: float = DEFAULT_SERVICE_TIMEOUT_S,
                 is_success: Callable[[Any], bool] | None = None) -> None:
        label = f"CbCallService({service_name!r})"
        self.srv_type = check_service_type(label, srv_type)
        self.service_name = check_name(label, "service", service_name)
        self.request = srv_type.Request() if request is None else request
        check_instance(label, "the request", self.request, srv_type.Request)
        self.call_timeout_s = check_duration(label, "timeout_s", timeout_s)
        if is_success is not None and not callable(is_success):
            raise TypeError(f"{label}: is_success must be callable(response) -> bool, got {is_success!r}")
        self.is_success = is_success
        self.call: ServiceCall | None = None
        self._client: Any = None

    def start(self) -> None:
        self._client = ros_context(self.sm).node.create_client(self.srv_type, self.service_name)
        self.call = ServiceCall(self._client, self.request, timeout_s=self.call_timeout_s,
                                on_response=self._on_response, on_failure=self._on_failure,
                                service_name=self.service_name)
        self.call.start(self.sm.now())

    def poll(self) -> None:
        if self.call is not None:
            self.call.poll(self.sm.now())

    def _on_response(self, response: Any) -> None:
        if self.is_success is not None and not self.is_success(response):
            self.finish(False, response=response,
                        reason=f"CbCallService({self.service_name!r}): the response was rejected: {response}")
        else:
            self.finish(True, response=response)

    def _on_failure(self, reason: str) -> None:
        self.finish(False, reason=f"CbCallService: {reason}")

    def stop(self) -> None:
        if self.call is not None:
            self.call.abandon()
        if self._client is not None:
            ros_context(self.sm).node.destroy_client(self._client)
            self._client = None
