"""``CpActionClient``: one action client owned by a client (SMACC2 Jazzy's CpActionClient<Action>).

It wraps ``smacc_py.ros.action_client.RosActionClient`` (goals never block; each goal is a
``GoalTicket``) and posts the outcome of every goal nobody abandoned, parameterised by the owning
client and its orthogonal (the same events as ClNav2Z, from the same code: ``event_posting_callbacks``):

* ``EvActionFeedback[Client, Or](feedback=..., action=...)`` for each feedback message;
* ``EvActionResult[Client, Or](outcome=..., result=..., ...)`` when the goal ends, whatever its status;
* then ``EvActionSucceeded``, ``EvActionAborted`` (also for a rejected goal) or ``EvActionCancelled``.

Result payloads carry ``action`` (the action name), ``result``, ``error_code`` and ``error_msg`` (the
result's fields when the action type has them, else 0 and ''). A goal abandoned with
``GoalTicket.abandon()`` (a behavior whose state exits) is cancelled and posts nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core import (
    EvActionAborted,
    EvActionCancelled,
    EvActionFeedback,
    EvActionResult,
    EvActionSucceeded,
    ISmaccClient,
    ISmaccComponent,
    SmaccError,
    SmaccEvent,
)
from smacc_py.ros.action_client import GoalOutcome, GoalTicket, RosActionClient
from smacc_py.ros.components.checks import check_action_type, check_instance, check_name
from smacc_py.ros.context import ros_context

OUTCOME_EVENTS: dict[GoalOutcome, type[SmaccEvent]] = {
    GoalOutcome.SUCCEEDED: EvActionSucceeded,
    GoalOutcome.ABORTED: EvActionAborted,
    GoalOutcome.REJECTED: EvActionAborted,
    GoalOutcome.CANCELED: EvActionCancelled,
}

DoneCallback = Callable[[GoalTicket], None]
FeedbackCallback = Callable[[GoalTicket, Any], None]


class CpActionClient(ISmaccComponent):
    """Client of the ``action_name`` server of type ``action_type`` (e.g. nav2_msgs.action.Wait)."""

    def __init__(self, action_type: Any, action_name: str) -> None:
        self.label = f"CpActionClient({action_name!r})"
        self.action_type = check_action_type(self.label, action_type)
        self.action_name = check_name(self.label, "action", action_name)
        self._client: RosActionClient | None = None

    def on_initialize(self) -> None:
        self._client = self.create_ros_client()

    def create_ros_client(self) -> RosActionClient:
        """The underlying non-blocking client; the one ROS endpoint a test stand-in overrides."""
        return RosActionClient(ros_context(self.sm).node, self.action_type, self.action_name)

    @property
    def ros_client(self) -> RosActionClient:
        """The underlying client; SmaccError before the machine was initialized."""
        if self._client is None:
            raise SmaccError(f"{self.label}: used before the machine was initialized")
        return self._client

    def server_ready(self) -> bool:
        """True once the action server is discovered."""
        return self._client is not None and self.ros_client.server_ready()

    def send_goal(self, goal: Any, on_done: DoneCallback | None = None,
                  on_feedback: FeedbackCallback | None = None) -> GoalTicket:
        """Send ``goal`` (an ``action_type.Goal``) at once; events, then ``on_done(ticket)`` /
        ``on_feedback(ticket, feedback)``, run on the executor thread. TypeError for another goal type."""
        check_instance(self.label, "the goal", goal, self.action_type.Goal)
        done, feedback = event_posting_callbacks(self.owner, self.action_name, on_done, on_feedback)
        return self.ros_client.send_goal(goal, done, feedback)

    def cancel_goals(self) -> None:
        """Ask the server to cancel every goal this component sent that has not ended (SMACC2 cancelGoal);
        their outcome events still come (usually EvActionCancelled)."""
        if self._client is not None:
            self._client.cancel_all()

    def active_goals(self) -> list[GoalTicket]:
        """Goals sent and not yet ended."""
        return [] if self._client is None else self._client.active_tickets()


def event_posting_callbacks(
    client: ISmaccClient, action: str, on_done: DoneCallback | None = None,
    on_feedback: FeedbackCallback | None = None,
) -> tuple[DoneCallback, FeedbackCallback]:
    """The done and feedback callbacks to give ``RosActionClient.send_goal`` so that ``client`` posts its
    EvAction* events about the goal (payload ``action``) before ``on_done`` / ``on_feedback`` run.

    Why a function and not only the component: a client with several action endpoints under keys of its
    own (ClNav2Z, whose payloads name the key even when the server name is remapped, and whose test
    stand-ins replace the endpoints themselves) posts exactly the same events, from this one place.
    """

    def done(ticket: GoalTicket) -> None:
        if not ticket.abandoned:
            assert ticket.outcome is not None  # on_done runs after GoalTicket.finish
            payload = {"action": action, "result": ticket.result, "error_code": ticket.error_code,
                       "error_msg": ticket.error_msg or describe_unexplained(ticket)}
            client.post_event(client.own_event(EvActionResult)(outcome=ticket.outcome, **payload))
            client.post_event(client.own_event(OUTCOME_EVENTS[ticket.outcome])(**payload))
        if on_done is not None:
            on_done(ticket)

    def feedback(ticket: GoalTicket, message: Any) -> None:
        if not ticket.abandoned:
            client.post_event(client.own_event(EvActionFeedback)(action=action, feedback=message))
        if on_feedback is not None:
            on_feedback(ticket, message)

    return done, feedback


def describe_unexplained(ticket: GoalTicket) -> str:
    """The message for an outcome whose result says nothing (a rejected goal has no result)."""
    if ticket.outcome is GoalOutcome.REJECTED:
        return f"{ticket.action_name} goal rejected"
    return ""
