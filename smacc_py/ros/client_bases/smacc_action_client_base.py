"""``SmaccActionClientBase``: the base of clients that talk to one ROS action server.

SMACC2's ``smacc2::client_bases::SmaccActionClientBase<ActionType>``. Subclass it with the action
type and the server name, configure it on an orthogonal, and its events arrive parameterised by your
class and that orthogonal::

    class ClWait(SmaccActionClientBase):
        def __init__(self, action_name: str = "wait") -> None:
            super().__init__(Wait, action_name)

    Transition(EvActionSucceeded[ClWait, OrWaiting], StDone)

Events (ABSOLUTE lifetime, see ``CpActionClient``): ``EvActionFeedback``, ``EvActionResult``, then one
of ``EvActionSucceeded`` / ``EvActionAborted`` / ``EvActionCancelled``, each ``[ClWait, OrWaiting]``.
Sending never blocks: ``send_goal`` returns a ``GoalTicket`` at once. Unlike SMACC2's base, a goal can
be disowned (``GoalTicket.abandon()``: cancelled, and no events): behaviors do that on state exit.

The work is done by a ``CpActionClient`` component created in ``on_initialize``; a subclass that
overrides ``on_initialize`` must call ``super().on_initialize()``.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient
from smacc_py.ros.action_client import GoalTicket
from smacc_py.ros.components.checks import check_action_type, check_created, check_name
from smacc_py.ros.components.cp_action_client import CpActionClient, DoneCallback, FeedbackCallback


class SmaccActionClientBase(ISmaccClient):
    """Client of action ``action_name`` of type ``action_type`` (e.g. nav2_msgs.action.Wait)."""

    def __init__(self, action_type: Any, action_name: str) -> None:
        label = f"{type(self).__name__}({action_name!r})"
        self.action_type = check_action_type(label, action_type)
        self.action_name = check_name(label, "action", action_name)
        self._action: CpActionClient | None = None

    def on_initialize(self) -> None:
        """Create the CpActionClient that holds the rclpy action client."""
        self._action = self.create_component(CpActionClient, self.action_type, self.action_name)

    @property
    def action(self) -> CpActionClient:
        """The component doing the work (SmaccError if ``super().on_initialize()`` was never called)."""
        return check_created(type(self).__name__, self._action, "CpActionClient")

    @property
    def goal_type(self) -> Any:
        """The goal message class (``action_type.Goal``)."""
        return self.action_type.Goal

    def server_ready(self) -> bool:
        """True once the action server is discovered (SMACC2 waitForServer, without waiting)."""
        return self.action.server_ready()

    def send_goal(self, goal: Any, on_done: DoneCallback | None = None,
                  on_feedback: FeedbackCallback | None = None) -> GoalTicket:
        """Send ``goal`` now; the events follow, then ``on_done(ticket)`` (executor thread)."""
        return self.action.send_goal(goal, on_done, on_feedback)

    def cancel_goal(self) -> None:
        """Cancel every goal of this client that is still running (SMACC2 cancelGoal)."""
        self.action.cancel_goals()

    def active_goals(self) -> list[GoalTicket]:
        """Goals sent and not yet ended."""
        return self.action.active_goals()
