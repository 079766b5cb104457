"""The demo's live line: state, pose, distance and ETA from NavigateToPose feedback, recoveries, RTF."""

from __future__ import annotations

from nav2_msgs.action import NavigateToPose

from smacc_py.clients.cl_nav2z import ClNav2Z
from smacc_py.core import EvActionFeedback
from smacc_py.ros.mission_status import MissionStatus
from smacc_py.state_machines.sm_nav2_test_1.orthogonals import OrNavigation


def _feedback(x: float, y: float, left_m: float, eta_s: int, recoveries: int) -> NavigateToPose.Feedback:
    feedback = NavigateToPose.Feedback()
    feedback.current_pose.pose.position.x, feedback.current_pose.pose.position.y = x, y
    feedback.distance_remaining = left_m
    feedback.estimated_time_remaining.sec = eta_s
    feedback.number_of_recoveries = recoveries
    return feedback


def test_the_line_shows_the_latest_navigation_feedback_until_the_state_ends() -> None:
    status = MissionStatus()
    assert status.line([], 0.0, 0.0) == "(starting) | sim 0.0 s"
    event = EvActionFeedback[ClNav2Z, OrNavigation]
    for action, feedback in (("navigate_to_pose", _feedback(1.0, 2.0, 9.0, 9, 0)),
                             ("navigate_to_pose", _feedback(1.234, -0.4, 2.26, 4, 1)),
                             ("something_else", None)):
        status.on_event_posted(None, event(action=action, feedback=feedback))  # type: ignore[arg-type]
    assert status.line(["StNavigateToWaypoint1"], 12.3, 2.4) == (
        "StNavigateToWaypoint1 | (1.23, -0.40) | 2.3 m left, ETA 4.0 s | recoveries 1 "
        "| sim 12.3 s, 5.1x real time")
    status.on_transition(None, None)  # type: ignore[arg-type]
    assert status.line(["StRotate"], 20.0, 4.0) == "StRotate | sim 20.0 s, 5.0x real time"
