"""``ServiceCall``: one service request, from waiting for the server to its answer or its deadline.

Why a class of its own: CpServiceClient (SM-lifetime) and CbCallService (state-lifetime, its own
client) make the same request in the same way. Nothing here blocks. The request leaves as soon as
the client sees the server (``service_is_ready``), checked now and on every ``poll``; the response
comes back through the future's done callback on the executor thread; ``poll`` (called from the
runtime's ISmaccUpdatable polling with the machine clock) ends the call with a failure once
``timeout_s`` seconds of machine clock (sim time under ``use_sim_time``) have passed. Exactly one
of ``on_response(response)`` and ``on_failure(reason)`` runs, unless the call was abandoned first.

A request is sent once: services are not assumed to be idempotent. (ros_tools.runtime.requests
resends queries whose answers DDS may drop; a caller that knows its service is idempotent can
retry on failure.)
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

_log = logging.getLogger("smacc_py")

ResponseCallback = Callable[[Any], None]
FailureCallback = Callable[[str], None]


class ServiceCall:
    """A request on ``client`` (an rclpy service client, or a fake with the same methods).

    Attributes:
        response: the response once answered, else None.
        failure: why the call failed, else None.
    """

    def __init__(self, client: Any, request: Any, *, timeout_s: float, on_response: ResponseCallback,
                 on_failure: FailureCallback, service_name: str) -> None:
        self.client, self.request, self.timeout_s = client, request, timeout_s
        self.service_name = service_name
        self.response: Any = None
        self.failure: str | None = None
        self._on_response, self._on_failure = on_response, on_failure
        self._lock = threading.Lock()
        self._future: Any = None
        self._finished = False
        self._deadline_s = 0.0

    @property
    def done(self) -> bool:
        """True once answered, failed or abandoned."""
        with self._lock:
            return self._finished

    @property
    def sent(self) -> bool:
        """True once the request left (the server was seen)."""
        return self._future is not None

    def start(self, now_s: float) -> None:
        """Arm the deadline (``now_s``: machine clock) and send at once if the server is there."""
        self._deadline_s = now_s + self.timeout_s
        self._send_if_ready()

    def poll(self, now_s: float) -> None:
        """Send once the server appears; fail once the deadline passed (``now_s``: machine clock)."""
        if self.done:
            return
        self._send_if_ready()
        if now_s >= self._deadline_s:
            what = "did not answer" if self.sent else "not available"
            self._finish(None, f"service '{self.service_name}' {what} within {self.timeout_s:g} s")

    def abandon(self) -> None:
        """Forget the call: no callback runs, and a pending request is withdrawn from the client."""
        with self._lock:
            self._finished = True
        self._withdraw()

    def _send_if_ready(self) -> None:
        if self._future is None and self.client.service_is_ready():
            self._future = self.client.call_async(self.request)
            self._future.add_done_callback(self._on_answer)

    def _on_answer(self, future: Any) -> None:
        try:
            response = future.result()
        except Exception as exc:  # the request was cancelled or the client destroyed
            self._finish(None, f"service '{self.service_name}' call failed: {exc}")
            return
        if response is None:
            self._finish(None, f"service '{self.service_name}' returned no response")
        else:
            self._finish(response, None)

    def _finish(self, response: Any, failure: str | None) -> None:
        with self._lock:
            if self._finished:
                return
            self._finished = True
        self.response, self.failure = response, failure
        if failure is None:
            self._on_response(response)
        else:
            self._withdraw()
            self._on_failure(failure)

    def _withdraw(self) -> None:
        future = self._future
        if future is not None and not future.done():
            try:
                self.client.remove_pending_request(future)
            except Exception:  # the client is gone already; nothing to withdraw
                _log.debug("%s: pending request already gone", self.service_name)
