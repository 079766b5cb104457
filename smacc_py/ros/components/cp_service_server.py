"""``CpServiceServer``: serves one service for a client (the endpoint of SmaccServiceServerClient).

Each request runs ``handler(request, response) -> response`` on the executor thread (SMACC2's
``onServiceRequestReceived`` signal), then ``EvServiceRequestReceived[Client, Or](request=...,
response=..., service=...)`` is posted so that a state can react to being called. A handler that
raises is logged; the caller then gets the response as the handler left it (often the default
values) and the event carries ``error`` with the exception's text. The handler must return quickly:
the machine's callbacks share one thread.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from smacc_py.core import ISmaccComponent, SmaccEvent
from smacc_py.ros.components.checks import check_name, check_service_type
from smacc_py.ros.context import ros_context

_log = logging.getLogger("smacc_py")

Handler = Callable[[Any, Any], Any]


class EvServiceRequestReceived(SmaccEvent):
    """A served service was called; parameters are (source, orthogonal). Payload ``request``,
    ``response`` (as returned to the caller), ``service`` and, when the handler raised, ``error``."""


class CpServiceServer(ISmaccComponent):
    """Server of ``service_name`` (``srv_type``) answering with ``handler``."""

    def __init__(self, srv_type: Any, service_name: str, handler: Handler) -> None:
        label = f"CpServiceServer({service_name!r})"
        self.srv_type = check_service_type(label, srv_type)
        self.service_name = check_name(label, "service", service_name)
        if not callable(handler):
            raise TypeError(f"{label}: handler must be callable(request, response) -> response, got "
                            f"{handler!r}")
        self.handler = handler
        self._service: Any = None

    def on_initialize(self) -> None:
        node = ros_context(self.sm).node
        self._service = node.create_service(self.srv_type, self.service_name, self.serve)

    def serve(self, request: Any, response: Any) -> Any:
        """Answer one request (the service callback): run the handler, post the event, return."""
        error: dict[str, str] = {}
        try:
            answer = self.handler(request, response)
            if answer is not None:
                response = answer
        except Exception as exc:
            _log.exception("%s: the handler raised; answering with the response as it was",
                           self.service_name)
            error["error"] = f"{type(exc).__name__}: {exc}"
        self.post_event(self.owner.own_event(EvServiceRequestReceived)(
            request=request, response=response, service=self.service_name, **error))
        return response
