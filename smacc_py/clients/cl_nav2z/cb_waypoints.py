"""Named-waypoint behaviors on CpWaypointNavigator: CbNavigateNamedWaypoint,
CbNavigateNextWaypointUntilReached and CbSeekWaypoint (SMACC2's names and meaning).

* ``CbNavigateNamedWaypoint(name)`` puts the cursor on the waypoint called ``name`` and navigates there
  as CbNavigateNextWaypoint does (EvWaypoint<i> from the navigator, then EvCbSuccess).
* ``CbNavigateNextWaypointUntilReached(goal_waypoint_name)`` navigates to the next waypoint; when the
  one reached is the goal it posts ``EvGoalWaypointReached[Cb, Or]`` before its EvCbSuccess. A state
  loops on EvCbSuccess (self-transition) and leaves on EvGoalWaypointReached: the success event of the
  goal leg is then dropped with the exited state.
* ``CbSeekWaypoint(name)`` or ``CbSeekWaypoint(count=n)`` only moves the cursor (to ``name``, or ``n``
  waypoints on) and posts EvCbSuccess with the new ``index``; SMACC2's posts nothing.

A name that no waypoint has is bad input found at run time (the list is loaded at machine start): the
behavior posts EvCbFailure with a ``reason`` naming itself, the field and the value, and sends nothing.
"""

from __future__ import annotations

from typing import Any

from smacc_py.clients.cl_nav2z.cb_navigation import CbNavigateNextWaypoint
from smacc_py.clients.cl_nav2z.cp_waypoint_navigator import CpWaypointNavigator
from smacc_py.core import EvGoalWaypointReached, SmaccClientBehavior
from smacc_py.ros.action_client import GoalOutcome, GoalTicket


def check_waypoint_name(behavior: str, field: str, name: object) -> str:
    """``name`` if it is a non-empty str; ValueError (TypeError) naming ``behavior`` and ``field``."""
    if not isinstance(name, str):
        raise TypeError(f"{behavior}: {field} must be a str, got {name!r}")
    if not name:
        raise ValueError(f"{behavior}: {field} is empty")
    return name


def unknown_waypoint(behavior: str, field: str, name: str, navigator: CpWaypointNavigator) -> str:
    """The failure reason for a name no waypoint has."""
    return (f"{behavior}: {field} {name!r} is not a waypoint of CpWaypointNavigator "
            f"(named: {navigator.named()})")


class CbNavigateNamedWaypoint(CbNavigateNextWaypoint):
    """Navigate to the waypoint called ``waypoint_name`` (the cursor moves there first)."""

    def __init__(self, waypoint_name: str, *, goal_checker: str | None = None) -> None:
        super().__init__(goal_checker=goal_checker)
        self.waypoint_name = check_waypoint_name("CbNavigateNamedWaypoint", "waypoint_name", waypoint_name)

    def make_goal(self) -> tuple[str, Any] | None:
        navigator = self.requires_component(CpWaypointNavigator)
        if navigator.find(self.waypoint_name) is None:
            self.post_failure_event(reason=unknown_waypoint(
                "CbNavigateNamedWaypoint", "waypoint_name", self.waypoint_name, navigator))
            return None
        navigator.seek_name(self.waypoint_name)
        return super().make_goal()


class CbNavigateNextWaypointUntilReached(CbNavigateNextWaypoint):
    """Navigate to the next waypoint; EvGoalWaypointReached once it is ``goal_waypoint_name``."""

    def __init__(self, goal_waypoint_name: str, *, goal_checker: str | None = None) -> None:
        super().__init__(goal_checker=goal_checker)
        self.goal_waypoint_name = check_waypoint_name(
            "CbNavigateNextWaypointUntilReached", "goal_waypoint_name", goal_waypoint_name)

    def make_goal(self) -> tuple[str, Any] | None:
        navigator = self.requires_component(CpWaypointNavigator)
        goal_index = navigator.find(self.goal_waypoint_name)
        current = navigator.current()
        reason = None
        if goal_index is None:
            reason = unknown_waypoint("CbNavigateNextWaypointUntilReached", "goal_waypoint_name",
                                      self.goal_waypoint_name, navigator)
        elif current is None or goal_index < current[0]:
            cursor = "past the last waypoint" if current is None else f"at waypoint {current[0]}"
            reason = (f"CbNavigateNextWaypointUntilReached: goal_waypoint_name {self.goal_waypoint_name!r} "
                      f"is waypoint {goal_index}, behind the cursor ({cursor})")
        if reason is not None:
            self.post_failure_event(reason=reason)
            return None
        return super().make_goal()

    def on_goal_done(self, ticket: GoalTicket) -> None:
        super().on_goal_done(ticket)
        if ticket.outcome is not GoalOutcome.SUCCEEDED:
            return
        reached = self.requires_component(CpWaypointNavigator).waypoints[self.index]
        if reached.name == self.goal_waypoint_name:
            event = self.own_event(EvGoalWaypointReached)(waypoint_index=self.index, name=reached.name)
            self.post_event(event)


class CbSeekWaypoint(SmaccClientBehavior):
    """Move CpWaypointNavigator's cursor to ``waypoint_name``, or ``count`` waypoints forward; no motion."""

    def __init__(self, waypoint_name: str | None = None, *, count: int | None = None) -> None:
        if (waypoint_name is None) == (count is None):
            raise ValueError(f"CbSeekWaypoint: give exactly one of waypoint_name and count, got "
                             f"{waypoint_name!r} and {count!r}")
        if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 0):
            raise ValueError(f"CbSeekWaypoint: count must be an int >= 0, got {count!r}")
        self.waypoint_name = (None if waypoint_name is None
                              else check_waypoint_name("CbSeekWaypoint", "waypoint_name", waypoint_name))
        self.count = count

    def on_entry(self) -> None:
        navigator = self.requires_component(CpWaypointNavigator)
        if self.waypoint_name is None:
            navigator.forward(self.count or 0)
        elif navigator.find(self.waypoint_name) is None:
            self.post_failure_event(reason=unknown_waypoint(
                "CbSeekWaypoint", "waypoint_name", self.waypoint_name, navigator))
            return
        else:
            navigator.seek_name(self.waypoint_name)
        self.post_success_event(index=navigator.current_index)
