"""A live one-line view of a running navigation mission, for the mission commands on a terminal.

Why: between two transitions a mission can run for a minute of sim time, and a console that only
prints transitions looks stalled. On a terminal the demos redraw one line: the active state, the
robot's pose, the distance left and Nav2's estimate of the time left, the recoveries so far and
the real-time factor. Piped, nothing is drawn (ros_tools.status_line), so logs keep plain lines.

The navigation figures come from NavigateToPose feedback (distance_remaining in m,
estimated_time_remaining, number_of_recoveries, current_pose in the map frame), which ClNav2Z posts
into the machine as EvActionFeedback; this observer keeps the latest one and forgets it when a
transition ends the state that was navigating.
"""

from __future__ import annotations

import threading
from typing import Any

from smacc_py.core import EvActionFeedback, SmaccEvent, SmaccObserver, SmaccStateMachineBase, TransitionRecord


class MissionStatus(SmaccObserver):
    """Keeps the latest NavigateToPose feedback; :meth:`line` formats the status line."""

    def __init__(self, action: str = "navigate_to_pose") -> None:
        self.action = action
        self._feedback: Any = None
        self._lock = threading.Lock()  # events are posted from the executor's thread

    def on_event_posted(self, sm: SmaccStateMachineBase, event: SmaccEvent) -> None:
        if isinstance(event, EvActionFeedback) and getattr(event, "action", None) == self.action:
            with self._lock:
                self._feedback = getattr(event, "feedback", None)

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        with self._lock:
            self._feedback = None

    def line(self, states: list[str], sim_s: float, wall_s: float) -> str:
        """``StNavigateToWaypoint1 | (1.23, -0.40) | 2.3 m left, ETA 4.1 s | recoveries 0 | sim 12.3 s,
        5.1x real time`` (the navigation parts only while a goal reports feedback)."""
        with self._lock:
            feedback = self._feedback
        parts = [" / ".join(states) or "(starting)"]
        if feedback is not None:
            p = feedback.current_pose.pose.position
            eta = feedback.estimated_time_remaining
            parts += [f"({p.x:.2f}, {p.y:.2f})",
                      f"{feedback.distance_remaining:.1f} m left, ETA {eta.sec + eta.nanosec * 1e-9:.1f} s",
                      f"recoveries {feedback.number_of_recoveries}"]
        rtf = f", {sim_s / wall_s:.1f}x real time" if wall_s > 0.0 else ""
        parts.append(f"sim {sim_s:.1f} s{rtf}")
        return " | ".join(parts)
