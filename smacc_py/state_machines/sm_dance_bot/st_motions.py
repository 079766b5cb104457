"""The top-level motion states of sm_dance_bot: StNavigateForward1-2, StNavigateReverse1-4,
StRotateDegrees1-6 (SMACC2: states/st_navigate_forward_*.hpp, st_navigate_reverse_*.hpp,
st_rotate_degrees_*.hpp).

Each one runs one cl_nav2z motion on OrNavigation, keeps the LED off and the lidar behavior on, and
returns to StNavigateToWaypointsX on failure, as upstream. SMACC2 drives these motions with its own
planner plugins (forward, backward, pure spinning); here CbNavigateForward, CbNavigateBackwards and
CbRotate use Nav2's behavior server (drive_on_heading, backup, spin). CbPauseSlam/CbResumeSlam are left
out: this stack localizes with AMCL on a known map. Distances are in waypoints.py (shorter than
upstream's, to fit turtlebot3_world); angles are upstream's.
"""

from __future__ import annotations

from smacc_py.clients.cl_nav2z import CbNavigateBackwards, CbNavigateForward, CbRotate
from smacc_py.core import ABORT, EvCbFailure, EvCbSuccess, SmaccState, Transition, TransitionTag
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import CbLEDOff, CbLidarSensor
from smacc_py.state_machines.sm_dance_bot.modestates import MsDanceBotRunMode
from smacc_py.state_machines.sm_dance_bot.orthogonals import OrLED, OrNavigation, OrObstaclePerception

WAYPOINTS_X = "StNavigateToWaypointsX"


class _Motion(SmaccState):
    """LED off and the lidar on, besides the state's motion."""

    @classmethod
    def configure_common(cls) -> None:
        cls.configure_orthogonal(OrLED, CbLEDOff)
        cls.configure_orthogonal(OrObstaclePerception, CbLidarSensor)


def _straight_state(name: str, behavior: type[CbNavigateForward | CbNavigateBackwards], distance: float,
                    following: str, failure_tag: type[TransitionTag] | None, doc: str) -> type[SmaccState]:
    """A straight motion of ``distance`` m, then ``following``; failure → StNavigateToWaypointsX."""
    ok, failed = EvCbSuccess[behavior, OrNavigation], EvCbFailure[behavior, OrNavigation]
    args = (distance, wp.FORWARD_SPEED) if behavior is CbNavigateForward else (distance,)

    @classmethod  # type: ignore[misc]
    def static_configure(cls: type[_Motion]) -> None:
        cls.configure_orthogonal(OrNavigation, behavior, *args)
        cls.configure_common()

    namespace = {
        "reactions": [Transition(ok, following), Transition(failed, WAYPOINTS_X, failure_tag)],
        "static_configure": static_configure, "__doc__": doc, "__module__": __name__, "__qualname__": name,
    }
    return type(name, (_Motion,), namespace, parent=MsDanceBotRunMode)


_F, _B = CbNavigateForward, CbNavigateBackwards
StNavigateForward1 = _straight_state("StNavigateForward1", _F, wp.FORWARD_1, "StRotateDegrees2", ABORT,
                                     "Forward (upstream 1 m), then StRotateDegrees2.")
StNavigateForward2 = _straight_state("StNavigateForward2", _F, wp.FORWARD_2, "StRotateDegrees5", None,
                                     "Forward (upstream 1 m), then StRotateDegrees5.")
StNavigateReverse1 = _straight_state("StNavigateReverse1", _B, wp.REVERSE_1, "StRotateDegrees3", None,
                                     "Backwards (upstream 2 m), then StRotateDegrees3.")
StNavigateReverse2 = _straight_state("StNavigateReverse2", _B, wp.REVERSE_2, WAYPOINTS_X, None,
                                     "Backwards (upstream 2 m), then StNavigateToWaypointsX.")
StNavigateReverse3 = _straight_state("StNavigateReverse3", _B, wp.REVERSE_3, "StNavigateToWaypoint1", None,
                                     "Backwards (upstream 2 m), then StNavigateToWaypoint1.")
StNavigateReverse4 = _straight_state("StNavigateReverse4", _B, wp.REVERSE_4, "StRotateDegrees5", None,
                                     "Backwards (upstream 0.5 m), then StRotateDegrees5.")


def _rotate_state(index: int, degrees: float, following: str, doc: str) -> type[SmaccState]:
    """``StRotateDegrees<index>``: rotate ``degrees`` relative, then ``following``; failure → waypoints."""
    name = f"StRotateDegrees{index}"

    @classmethod  # type: ignore[misc]
    def static_configure(cls: type[_Motion]) -> None:
        cls.configure_orthogonal(OrNavigation, CbRotate, degrees)
        cls.configure_common()

    namespace = {
        "reactions": [Transition(EvCbSuccess[CbRotate, OrNavigation], following),
                      Transition(EvCbFailure[CbRotate, OrNavigation], WAYPOINTS_X)],
        "static_configure": static_configure, "__doc__": doc, "__module__": __name__, "__qualname__": name,
    }
    return type(name, (_Motion,), namespace, parent=MsDanceBotRunMode)


StRotateDegrees1 = _rotate_state(1, 90.0, "StNavigateForward1", "Rotate +90°, then StNavigateForward1.")
StRotateDegrees2 = _rotate_state(2, -90.0, WAYPOINTS_X, "Rotate -90°, then StNavigateToWaypointsX.")
StRotateDegrees3 = _rotate_state(3, 180.0, WAYPOINTS_X, "Rotate 180°, then StNavigateToWaypointsX.")
StRotateDegrees4 = _rotate_state(4, -180.0, "StNavigateReverse2", "Rotate -180°, then StNavigateReverse2.")
StRotateDegrees5 = _rotate_state(5, -180.0, WAYPOINTS_X, "Rotate -180°, then StNavigateToWaypointsX.")
StRotateDegrees6 = _rotate_state(6, -180.0, "StNavigateReverse3", "Rotate -180°, then StNavigateReverse3.")
