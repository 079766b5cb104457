"""What the ROS-backed BT leaves share: the node, cached clients, TF and failures.

One thread: the bt_navigator ticks its tree from a timer on the same single-threaded executor
that receives every leaf's responses. rclpy registers a goal request's future only after the
request has left, and a response handled by another thread in between would be dropped
("unexpected goal response"); with one thread sending and receiving never interleave.

Why cached clients: a new DDS client needs discovery (hundreds of ms) before its server is seen;
trees are rebuilt per goal, their clients are not.

``failures`` keeps, per ``error_code_id`` blackboard key, the last failure a leaf saw (server,
code, code name, message), so the navigator can put the failing server's code and message in
its own result; the latest one also when no server set a code (a goal never acknowledged).

Two clocks: ``wall_clock`` (steady, s) times the wait for a server to appear, because DDS discovery
takes wall time; ``clock`` (the node's, s: sim time under ``use_sim_time``) times a server's answer.
Nav2 times both on the steady clock, which under lockstep at ``--rtf max`` makes a goal fail or not
depending on how loaded the machine is: a one-second stall of a busy process is a second of wall
time but no sim time at all, since the simulator waits for it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rclpy.action import ActionClient
from rclpy.client import Client
from rclpy.node import Node

from nav_stack.ros.common.frames import Frames
from ros_tools.runtime.lockstep import REQUEST_HOLD, hold_process


@dataclass(frozen=True)
class LeafFailure:
    """The last unsuccessful outcome of one BT leaf (codes are the server's Jazzy result codes)."""

    server: str
    code: int
    code_name: str
    message: str

    def describe(self) -> str:
        """``planner_server 'compute_path_to_pose' failed with 206 (GOAL_OCCUPIED): <message>``."""
        name = f" ({self.code_name})" if self.code_name else ""
        text = f"'{self.server}' failed with error code {self.code}{name}"
        return f"{text}: {self.message}" if self.message else text


def code_name(result_type: Any, code: int) -> str:
    """Name of ``code`` among the result type's uint16 constants (``GOAL_OCCUPIED``), or ''."""
    for name in dir(result_type):
        if name.isupper() and name != "SLOT_TYPES" and getattr(result_type, name) == code:
            return name
    return ""


@dataclass
class TimedRequest:
    """A request whose answer a leaf waits for at most ``server_timeout`` ms of node clock.

    Attributes:
        future: the answer (a goal handle or a service response).
        sent_at: node clock (s) the wait counts from.
        held_until: steady clock (s) until which a lockstep simulator waits for the answer; None when
            no simulator waits (no lockstep participant in this process).
    """

    future: Any
    sent_at: float
    held_until: float | None


class BtRosContext:
    """Collaborators injected into every ROS-backed leaf (``factory.register(..., ros=ctx)``)."""

    def __init__(self, node: Node, frames: Frames | None = None,
                 wall_clock: Callable[[], float] | None = None,
                 clock: Callable[[], float] | None = None) -> None:
        import time

        self.node = node
        self.frames = frames
        self.wall_clock = wall_clock or time.monotonic
        self.clock = clock or (lambda: node.get_clock().now().nanoseconds * 1e-9)
        self._actions: dict[tuple[type, str], ActionClient] = {}
        self._services: dict[tuple[type, str], Client] = {}
        self._failures: dict[str, LeafFailure] = {}
        self._latest: LeafFailure | None = None
        self._lock = threading.Lock()
        self.global_frame = "map"
        self.robot_base_frame = "base_link"
        self.transform_tolerance = 0.1  # s

    def start_timed(self, pending: Any) -> TimedRequest:
        """Start timing the answer ``pending`` (a future), and keep a lockstep simulator from stepping
        on until it is done (at most REQUEST_HOLD wall s): a sim-time ``server_timeout`` must not race
        the wall time the request spends in DDS and in the server's queue. Its completion sends the
        withheld progress report at once."""
        held = hold_process(pending.done, wake=pending)
        return TimedRequest(pending, self.clock(), self.wall_clock() + REQUEST_HOLD if held else None)

    def waited_ms(self, request: TimedRequest) -> float:
        """ms of node clock ``request`` has waited for its answer, not counting the time the simulator
        was held for it.

        Why: a participant's report lets the simulator run up to ``lockstep.max_lead`` (50 ms) ahead
        of it, so while the simulator waits for the answer, the node clock may still pass the lead,
        more than Nav2's 20 ms default_server_timeout, and a goal would fail or not by the machine's
        load. While the hold lasts, no sim time counts; after it (a server that does not answer within
        REQUEST_HOLD wall s), the timeout runs in sim time as Nav2's does.
        """
        if request.held_until is not None and self.wall_clock() < request.held_until:
            request.sent_at = self.clock()
            return 0.0
        return (self.clock() - request.sent_at) * 1000.0

    def action_client(self, action_type: type, name: str) -> ActionClient:
        """The (cached) client of action ``name``."""
        key = (action_type, name)
        with self._lock:
            if key not in self._actions:
                self._actions[key] = ActionClient(self.node, action_type, name)
            return self._actions[key]

    def service_client(self, srv_type: type, name: str) -> Client:
        """The (cached) client of service ``name``."""
        key = (srv_type, name)
        with self._lock:
            if key not in self._services:
                self._services[key] = self.node.create_client(srv_type, name)
            return self._services[key]

    # -- failures ------------------------------------------------------------------------------
    def record_failure(self, key: str, failure: LeafFailure) -> None:
        """Remember the last failure written through error-code blackboard key ``key``."""
        self._failures[key] = failure
        self._latest = failure

    def failure(self, key: str) -> LeafFailure | None:
        """The last failure recorded for ``key``."""
        return self._failures.get(key)

    @property
    def latest_failure(self) -> LeafFailure | None:
        """The failure recorded last, whatever its key (None since :meth:`clear_failures`)."""
        return self._latest

    def clear_failures(self) -> None:
        """Forget all failures (at the start of each navigation)."""
        self._failures.clear()
        self._latest = None

    def destroy(self) -> None:
        """Destroy every cached client."""
        with self._lock:
            for client in self._actions.values():
                client.destroy()
            for service in self._services.values():
                self.node.destroy_client(service)
            self._actions.clear()
            self._services.clear()
