"""``ServiceCaller``: the base of cl_nav2z components that call ROS services (CpSlamToolbox, CpCostmapSwitch).

Why a base: both components send requests from the machine thread and hear the answer later, and
neither may wait for it. Each request is a ``ServiceCall`` (smacc_py.ros.components): it leaves as
soon as the client sees the server, and its answer comes back through the future's done callback
on the executor thread. This base keeps the calls in flight and, from the runtime's ISmaccUpdatable
polling, sends the ones whose server has appeared and fails the ones past their deadline.

A call fails once ``timeout_s`` seconds have passed on both the machine clock and the wall clock:
the machine clock (sim time under ``use_sim_time``) keeps the wait at least that long in sim time,
and the wall clock covers DDS discovery, which takes wall time however fast the simulation runs
(the same rule as CbNav2ZActionBase's server wait).

Every ROS endpoint is made by ``make_client``, so a test stand-in overrides that one method (and
``wall_now``, to put a scripted world's clock in place of the wall clock).
"""

from __future__ import annotations

import threading
import time
from typing import Any

from smacc_py.core import ISmaccComponent, ISmaccUpdatable
from smacc_py.ros.components.service_call import FailureCallback, ResponseCallback, ServiceCall
from smacc_py.ros.context import ros_context

DEFAULT_CALL_TIMEOUT_S = 10.0  # s (machine clock and wall clock) from the request to its answer


class ServiceCaller(ISmaccComponent, ISmaccUpdatable):
    """Keeps this component's service calls in flight; subclasses call ``call_service``."""

    def __init__(self) -> None:
        self._calls: list[tuple[ServiceCall, float, float]] = []  # call, machine s, wall s at the start
        self._calls_lock = threading.Lock()

    def make_client(self, srv_type: Any, service_name: str) -> Any:
        """A service client of the machine's node (a stand-in returns a fake with the same methods)."""
        return ros_context(self.sm).node.create_client(srv_type, service_name)

    def wall_now(self) -> float:
        """The wall clock (s, monotonic) that bounds discovery."""
        return time.monotonic()

    def call_service(self, client: Any, request: Any, *, service_name: str, timeout_s: float,
                     on_response: ResponseCallback, on_failure: FailureCallback) -> ServiceCall:
        """Send ``request`` on ``client`` as soon as its server is seen; never blocks. Exactly one of
        ``on_response(response)`` and ``on_failure(reason)`` runs later, unless the call is abandoned."""
        call = ServiceCall(client, request, timeout_s=timeout_s, on_response=on_response,
                           on_failure=on_failure, service_name=service_name)
        with self._calls_lock:
            self._calls = [entry for entry in self._calls if not entry[0].done]
            self._calls.append((call, self.sm.now(), self.wall_now()))
        call.start(0.0)  # deadlines count from 0: update() polls with the time elapsed on both clocks
        return call

    def update(self) -> None:
        """Send calls whose server appeared; fail those whose deadline passed on both clocks."""
        with self._calls_lock:
            self._calls = [entry for entry in self._calls if not entry[0].done]
            calls = list(self._calls)
        now_s, now_wall = self.sm.now(), self.wall_now()
        for call, since_s, since_wall in calls:
            call.poll(min(now_s - since_s, now_wall - since_wall))
