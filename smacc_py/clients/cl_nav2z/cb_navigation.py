"""Goal-pose navigation behaviors on NavigateToPose: CbNavigateGlobalPosition, CbNavigateNextWaypoint,
CbStopNavigation, CbAbortNavigation."""

from __future__ import annotations

from typing import Any

from nav2_msgs.action import NavigateToPose

from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.clients.cl_nav2z.client import NAVIGATE_TO_POSE, ClNav2Z
from smacc_py.clients.cl_nav2z.cp_pose import CpPose, make_pose_stamped
from smacc_py.clients.cl_nav2z.cp_switchers import CpGoalCheckerSwitcher, CpPlannerSwitcher
from smacc_py.clients.cl_nav2z.cp_waypoint_navigator import CpWaypointNavigator
from smacc_py.core import SmaccClientBehavior
from smacc_py.ros.action_client import GoalOutcome, GoalTicket


class CbNavigateGlobalPosition(CbNav2ZActionBase):
    """Navigate to (x, y in m, yaw in rad) in the CpPose reference frame (map) with Nav2's default
    planner/controller and goal checker; records the path in CpOdomTracker while moving.

    A state may change the goal in its ``runtime_configure`` with ``set_goal`` (e.g. from parameters).
    """

    def __init__(
        self,
        x: float,
        y: float,
        yaw: float = 0.0,
        *,
        goal_checker: str | None = None,
        frame_id: str | None = None,
    ) -> None:
        self.goal = (float(x), float(y), float(yaw))
        self.goal_checker, self.frame_id = goal_checker, frame_id

    def set_goal(self, x: float, y: float, yaw: float) -> None:
        """Replace the goal (before ``on_entry``)."""
        self.goal = (float(x), float(y), float(yaw))

    def goal_frame(self) -> str:
        """The frame of the goal: ``frame_id``, else CpPose's reference frame, else map."""
        if self.frame_id:
            return self.frame_id
        pose = self.optional_component(CpPose)
        return pose.reference_frame if pose is not None else "map"

    record_path = True

    def prepare(self) -> None:
        """Select Nav2's default planner/controller and the goal checker."""
        switcher = self.optional_component(CpPlannerSwitcher)
        if switcher is not None:
            switcher.set_default_planners()
        checker = self.optional_component(CpGoalCheckerSwitcher)
        if checker is not None:
            checker.set_goal_checker_id(self.goal_checker)

    def make_goal(self) -> tuple[str, Any] | None:
        self.prepare()
        pose = make_pose_stamped(self.goal_frame(), *self.goal, stamp=self.sm.now())
        return NAVIGATE_TO_POSE, NavigateToPose.Goal(pose=pose)


class CbNavigateNextWaypoint(CbNavigateGlobalPosition):
    """Navigate to the waypoint under CpWaypointNavigator's cursor; success posts EvWaypoint<i>."""

    def __init__(self, *, goal_checker: str | None = None) -> None:
        super().__init__(0.0, 0.0, 0.0, goal_checker=goal_checker)
        self.index = -1

    def make_goal(self) -> tuple[str, Any] | None:
        current = self.requires_component(CpWaypointNavigator).current()
        if current is None:
            self.post_failure_event(reason="no waypoint left (cursor past the end)")
            return None
        self.index, waypoint = current
        self.set_goal(waypoint.x, waypoint.y, waypoint.yaw)
        return super().make_goal()

    def on_goal_done(self, ticket: GoalTicket) -> None:
        if ticket.outcome is GoalOutcome.SUCCEEDED:
            self.requires_component(CpWaypointNavigator).on_reached(self.index)


class CbAbortNavigation(SmaccClientBehavior):
    """Cancel every goal of the navigate_to_pose server (CancelGoal with zero id and stamp), then succeed
    with ``goals_canceling`` (how many the server is canceling).

    Without a server, or without its answer, there is nothing to cancel: success with a ``reason``.
    """

    def on_entry(self) -> None:
        client = self.requires_client(ClNav2Z)
        client.cancel_navigation()
        client.cancel_every_navigation_goal(lambda canceling: self._on_answer(client, canceling))

    def _on_answer(self, client: ClNav2Z, canceling: int | None) -> None:
        if canceling is None:
            self.post_success_event(reason=f"no answer from {client.cancel_service_name}: nothing to cancel")
        else:
            self.post_success_event(goals_canceling=canceling)


class CbStopNavigation(SmaccClientBehavior):
    """Cancel this client's navigation goals and command a zero twist on ClNav2Z's cmd_vel, then succeed."""

    def on_entry(self) -> None:
        client = self.requires_client(ClNav2Z)
        client.cancel_navigation()
        client.publish_twist()
        self.post_success_event()
