"""A NavigateToPose client for GoToPose that never blocks (rclpy futures and done-callbacks).

The tree polls ``RosNavGoal.outcome()`` on each tick; the goal response and the result arrive on
the executor and only set fields. A cancel asked for before the server accepted the goal is sent
as soon as it is accepted, so a halted GoToPose never leaves a goal behind.

A request (or its acknowledgement) can be lost while DDS completes a match, under load or after
the stack restarts (ros_tools.runtime.actions.send_until_acknowledged says how). A coroutine sends
the goal again every few seconds until the server answers; before, a lost request left the mission
"going to location1" until the tree's own timeout.

A server that is lost under an accepted goal (its process died; a respawned bt_navigator does not know
the goal) ends the goal ABORTED with Nav2's UNKNOWN code (SERVER_LOST_CODE) as soon as
ros_tools.runtime.action_watch notices it, so GoToPose fails and the tree's own retry or fallback acts
instead of waiting for ever for a result.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from action_msgs.msg import GoalStatus
from nav2_msgs.action import NavigateToPose
from rclpy.action import ActionClient
from rclpy.node import Node

from nav_stack.ros.autonomy.locations import Location
from nav_stack.ros.autonomy.seed_nodes import NavOutcome
from nav_stack.ros.common.conversions import pose_stamped
from ros_tools.runtime.action_watch import ServerLossWatch
from ros_tools.runtime.actions import ACK_RETRY_S, Withdrawals, acknowledged
from ros_tools.runtime.coroutines import spawn

#: copies of a goal sent (ACK_RETRY_S s apart) before the goal is given up as aborted.
SENDS = 6
#: the error code of a goal whose server was lost: Nav2's UNKNOWN, bt_navigator's code for its own faults
SERVER_LOST_CODE = 9000
Watch = Callable[[Any, Callable[[str], None]], Callable[[], None]]

_STATUS = {
    GoalStatus.STATUS_SUCCEEDED: NavOutcome.SUCCEEDED,
    GoalStatus.STATUS_CANCELED: NavOutcome.CANCELED,
    GoalStatus.STATUS_ABORTED: NavOutcome.ABORTED,
}


class RosNavGoal:
    """One goal; fields are written by executor callbacks and read by the tree (under a lock)."""

    def __init__(self, watch: Watch | None = None) -> None:
        self._watch = watch  # ServerLossWatch.watch of the navigator's action
        self._unwatch: Callable[[], None] | None = None
        self._lock = threading.Lock()
        self._outcome: NavOutcome | None = None
        self._detail = ""
        self._handle: Any = None
        self._cancel_requested = False
        self._cancel_future: Any = None  # the cancel request's response, once one was sent
        self._withdrawals = Withdrawals()  # copies sent while unwanted, canceled if the server accepts them

    def outcome(self) -> NavOutcome | None:
        with self._lock:
            return self._outcome

    def detail(self) -> str:
        with self._lock:
            return self._detail

    def cancel(self) -> None:
        with self._lock:
            self._cancel_requested = True
            handle = self._handle if self._outcome is None else None
        if handle is not None:
            self._send_cancel(handle)

    def _send_cancel(self, handle: Any) -> None:
        future = handle.cancel_goal_async()
        with self._lock:
            self._cancel_future = future

    def cancel_answered(self) -> bool:
        """No cancel is still on its way: sent and unanswered, or asked for before the server
        acknowledged the goal (it is sent with the acknowledgement), or for a copy the server
        accepted after the goal was given up."""
        if not self._withdrawals.settled():
            return False
        with self._lock:
            if self._cancel_future is not None:
                return bool(self._cancel_future.done())
            return not (self._cancel_requested and self._handle is None and self._outcome is None)

    def _finish(self, outcome: NavOutcome, detail: str = "") -> None:
        with self._lock:
            if self._outcome is None:
                self._outcome, self._detail = outcome, detail
            unwatch, self._unwatch = self._unwatch, None
        if unwatch is not None:
            unwatch()

    def _on_server_lost(self, why: str) -> None:
        self._finish(NavOutcome.ABORTED, f"error_code {SERVER_LOST_CODE}: server lost: {why}")

    def _canceled(self) -> bool:
        with self._lock:
            return self._cancel_requested

    def _on_goal_response(self, future: Any) -> None:
        handle = future.result()
        if handle is None or not handle.accepted:
            self._finish(NavOutcome.REJECTED, "goal rejected by the server")
            return
        with self._lock:
            self._handle = handle
            cancel = self._cancel_requested
        if self._watch is not None:
            unwatch = self._watch(handle.goal_id, self._on_server_lost)
            with self._lock:
                self._unwatch = unwatch
        handle.get_result_async().add_done_callback(self._on_result)
        if cancel:
            self._send_cancel(handle)

    def _on_result(self, future: Any) -> None:
        response = future.result()
        if response is None:
            self._finish(NavOutcome.ABORTED, "no result")
            return
        result = response.result
        code = int(getattr(result, "error_code", 0) or 0)
        message = str(getattr(result, "error_msg", "") or "")
        detail = f"error_code {code}: {message}" if code or message else ""
        self._finish(_STATUS.get(response.status, NavOutcome.ABORTED), detail)


class RosNavigator:
    """NavigateToPose client on ``action_name``; goals in ``frame`` stamped with the node clock."""

    def __init__(self, node: Node, action_name: str = "navigate_to_pose", frame: str = "map",
                 callback_group: Any = None) -> None:
        self.node = node
        self.action_name = action_name
        self.frame = frame
        self._client = ActionClient(node, NavigateToPose, action_name, callback_group=callback_group)
        self._server_watch = ServerLossWatch(node, NavigateToPose, action_name)
        self._goals: list[RosNavGoal] = []  # sent and not yet ended (or with a cancel in flight)

    def server_ready(self) -> bool:
        return bool(self._client.server_is_ready())

    def send(self, location: Location) -> RosNavGoal:
        goal = RosNavGoal(self._server_watch.watch)
        stamp = self.node.get_clock().now().to_msg()
        pose = pose_stamped(location.x, location.y, location.theta, self.frame, stamp)
        spawn(self.node, self._send(goal, NavigateToPose.Goal(pose=pose)))
        self._goals = [g for g in self._goals if g.outcome() is None or not g.cancel_answered()] + [goal]
        return goal

    def cancels_answered(self) -> bool:
        """Every cancel sent for this navigator's goals has its answer: the server has it, so the
        process may exit (a request still in this process's DDS queue dies with it)."""
        return all(goal.cancel_answered() for goal in self._goals)

    async def _send(self, goal: RosNavGoal, request: NavigateToPose.Goal) -> None:
        answer = await acknowledged(self.node, self._client, request, SENDS,
                                    wanted=lambda: not goal._canceled(), withdrawals=goal._withdrawals)
        if answer is not None:
            goal._on_goal_response(answer)
        elif goal._canceled():
            goal._finish(NavOutcome.CANCELED, "canceled before the server acknowledged the goal")
        else:
            goal._finish(NavOutcome.ABORTED, f"'{self.action_name}' acknowledged none of {SENDS} "
                                             f"copies of the goal ({SENDS * ACK_RETRY_S:.0f} s)")

    def destroy(self) -> None:
        """Destroy the action client unless it is gone already (the runner's teardown destroys every
        waitable of a node before the node itself)."""
        if any(waitable is self._client for waitable in self.node.waitables):
            self._client.destroy()
