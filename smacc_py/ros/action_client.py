"""A non-blocking action client: goals are tickets, results arrive through callbacks.

Why not rclpy's ``ActionClient.send_goal``: it blocks. Everything here returns at once; the goal
response, the feedback and the result come back on the executor and are handed to the callbacks
given with the goal (which only post events). Every goal gets a ``GoalTicket`` that knows its outcome,
the Nav2 ``error_code``/``error_msg`` of the result, and can be cancelled. ``abandon()`` is the cancel
a behavior issues when its state exits: the goal is cancelled and the ticket marked, so the client
posts no events for a goal nobody owns any more (SMACC2 checks goal ownership nowhere).
"""

from __future__ import annotations

import enum
import logging
import threading
import time
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from action_msgs.msg import GoalStatus

from ros_tools.runtime.lockstep import hold_process

if TYPE_CHECKING:
    from rclpy.node import Node

_log = logging.getLogger("smacc_py")


class GoalOutcome(enum.Enum):
    """How a goal ended."""

    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    CANCELED = "canceled"
    REJECTED = "rejected"


_STATUS = {
    GoalStatus.STATUS_SUCCEEDED: GoalOutcome.SUCCEEDED,
    GoalStatus.STATUS_CANCELED: GoalOutcome.CANCELED,
    GoalStatus.STATUS_ABORTED: GoalOutcome.ABORTED,
}


class GoalTicket:
    """One goal sent by a RosActionClient; ``outcome`` is None until it ended."""

    def __init__(self, action_name: str, goal: Any) -> None:
        self.action_name = action_name
        self.goal = goal
        self.outcome: GoalOutcome | None = None
        self.result: Any = None
        self.abandoned = False
        self._lock = threading.Lock()
        self._handle: Any = None
        self._cancel_requested = False
        self._done = threading.Event()
        self.sent_at = time.monotonic()  # wall s: what a wait that never ends is measured against
        self.accepted_at: float | None = None  # wall s the server's acceptance arrived
        self.feedbacks = 0  # feedback messages received: a server that still sends them is alive
        self.last_feedback_at: float | None = None  # wall s

    @property
    def done(self) -> bool:
        """True once the outcome is known."""
        return self._done.is_set()

    @property
    def goal_id(self) -> Any:
        """The accepted goal's unique_identifier_msgs/UUID, None until the server accepted it."""
        with self._lock:
            return None if self._handle is None else self._handle.goal_id

    @property
    def cancel_requested(self) -> bool:
        """True once ``cancel`` (or ``abandon``) was called."""
        with self._lock:
            return self._cancel_requested

    @property
    def error_code(self) -> int:
        """The result's Nav2 error code (0 when none or not applicable)."""
        return int(getattr(self.result, "error_code", 0) or 0)

    @property
    def error_msg(self) -> str:
        """The result's Nav2 error message ('' when none)."""
        return str(getattr(self.result, "error_msg", "") or "")

    def describe(self) -> str:
        """Human-readable outcome, e.g. ``aborted (error_code 204: goal outside map)``."""
        if self.outcome is None:
            return "pending"
        if self.error_code or self.error_msg:
            return f"{self.outcome.value} (error_code {self.error_code}: {self.error_msg})"
        return self.outcome.value

    def waiting_for(self, now: float | None = None) -> str:
        """What a pending goal waits for, in wall seconds, e.g. ``NavigateToPose goal: accepted 95.2 s
        ago, 812 feedback messages, the last 0.1 s ago`` (a server alive and working) or ``... sent
        12.0 s ago, not accepted yet`` (the request or its answer is lost, or the server is gone)."""
        now = time.monotonic() if now is None else now
        name = self.action_name.rsplit("/", 1)[-1] or self.action_name
        if self.done:
            return f"{name} goal: {self.describe()}"
        if self.accepted_at is None:
            return f"{name} goal: sent {now - self.sent_at:.1f} s ago, not accepted yet"
        if self.last_feedback_at is None:
            return f"{name} goal: accepted {now - self.accepted_at:.1f} s ago, no feedback yet"
        return (f"{name} goal: accepted {now - self.accepted_at:.1f} s ago, {self.feedbacks} feedback "
                f"messages, the last {now - self.last_feedback_at:.1f} s ago")

    def finish(self, outcome: GoalOutcome, result: Any) -> None:
        """Record how the goal ended (its action client calls this when the result arrives)."""
        self.outcome, self.result = outcome, result
        self._done.set()

    def cancel(self) -> None:
        """Ask the server to cancel the goal (now, or as soon as it was accepted)."""
        with self._lock:
            self._cancel_requested = True
            handle = self._handle
        if handle is not None and not self.done:
            handle.cancel_goal_async()

    def abandon(self) -> None:
        """Cancel and disown: the owner no longer wants events about this goal."""
        self.abandoned = True
        self.cancel()

    def wait(self, timeout_s: float) -> bool:
        """Block the calling (non-executor) thread up to ``timeout_s`` s for the outcome; tests use it."""
        return self._done.wait(timeout_s)


#: every goal this process sent that is still referenced (tickets are dropped with their owners)
_SENT: weakref.WeakSet[GoalTicket] = weakref.WeakSet()


def pending_goals() -> list[str]:
    """What each goal of this process that has not ended waits for (``GoalTicket.waiting_for``), oldest
    first: what a state machine that times out in a state says it was waiting for."""
    tickets = sorted((t for t in list(_SENT) if not t.done and not t.abandoned), key=lambda t: t.sent_at)
    return [ticket.waiting_for() for ticket in tickets]


DoneCallback = Callable[[GoalTicket], None]
FeedbackCallback = Callable[[GoalTicket, Any], None]


class RosActionClient:
    """Wraps an rclpy ActionClient; ``send_goal`` never blocks."""

    def __init__(self, node: Node, action_type: Any, action_name: str) -> None:
        # Imported here: rclpy.action loads rclpy.node, which importing cl_nav2z (e.g. for unit tests on
        # substitute clients, which never build a RosActionClient) does not need.
        from rclpy.action import ActionClient

        self.action_type = action_type
        self.action_name = action_name
        self._client = ActionClient(node, action_type, action_name)
        self._lock = threading.Lock()
        self._active: list[GoalTicket] = []

    def server_ready(self) -> bool:
        """True when an action server of that name is discovered."""
        return bool(self._client.server_is_ready())

    def active_tickets(self) -> list[GoalTicket]:
        """Goals sent and not yet ended."""
        with self._lock:
            return [t for t in self._active if not t.done]

    def send_goal(
        self, goal: Any, on_done: DoneCallback | None = None, on_feedback: FeedbackCallback | None = None
    ) -> GoalTicket:
        """Send ``goal``; ``on_done(ticket)`` and ``on_feedback(ticket, feedback)`` run on the executor."""
        ticket = GoalTicket(self.action_name, goal)
        _SENT.add(ticket)
        with self._lock:
            self._active = [t for t in self._active if not t.done] + [ticket]

        def feedback(message: Any) -> None:
            ticket.feedbacks += 1
            ticket.last_feedback_at = time.monotonic()
            if on_feedback is not None and not ticket.done:
                on_feedback(ticket, message.feedback)

        def finish(outcome: GoalOutcome, result: Any) -> None:
            ticket.finish(outcome, result)
            if on_done is not None:
                on_done(ticket)

        def on_result(future: Any) -> None:
            response = future.result()
            if response is None:
                finish(GoalOutcome.ABORTED, None)
                return
            finish(_STATUS.get(response.status, GoalOutcome.ABORTED), response.result)

        def on_goal_response(future: Any) -> None:
            handle = future.result()
            if handle is None or not handle.accepted:
                finish(GoalOutcome.REJECTED, None)
                return
            ticket.accepted_at = time.monotonic()
            with ticket._lock:
                ticket._handle = handle
                cancel = ticket._cancel_requested
            handle.get_result_async().add_done_callback(on_result)
            if cancel:
                handle.cancel_goal_async()

        accepted = self._client.send_goal_async(goal, feedback_callback=feedback)
        accepted.add_done_callback(on_goal_response)
        # In lockstep, sim time waits for the server's answer (REQUEST_HOLD wall s at most): seen
        # under load, the seed mission's first NavigateToPose goal took 1.4 s of wall time to be
        # accepted while the simulator ran 12 s of sim time with the robot standing still.
        hold_process(accepted.done, wake=accepted)
        return ticket

    def cancel_all(self) -> None:
        """Cancel every goal this client sent that has not ended."""
        for ticket in self.active_tickets():
            ticket.cancel()

    def destroy(self) -> None:
        """Destroy the underlying rclpy client."""
        self._client.destroy()
