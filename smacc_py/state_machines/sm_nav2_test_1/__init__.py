"""sm_nav2_test_1: SMACC2's sm_nav2_gazebo_test_1 (Jazzy) on smacc_py, against a Nav2-compatible stack.

StAllSensorsGo → StSetInitialPose → StNavigateToWaypoint1 → StRotate → StNavigateToWaypoint2 →
StFinalState, with the orthogonals OrTimer, OrKeyboard and OrNavigation (reference/smacc2.md §2); a lost
navigator (issue 45) goes through StRecoverNavigation1/2 and back to its waypoint.
Run it with ``smacc-run sm_nav2_test_1`` or the whole mission with ``navsuite-demo``; waypoints are ROS
parameters (config/sm_nav2_test_1.yaml), so editing one needs no rebuild.
"""

from smacc_py.state_machines.sm_nav2_test_1.sm_nav2_test_1 import (
    NOMINAL_TRANSITIONS,
    SmNav2Test1,
    SmNav2Test1Params,
)
from smacc_py.state_machines.sm_nav2_test_1.states import (
    NAV2_READY,
    NEXT,
    EvMaxRetriesExceeded,
    StAllSensorsGo,
    StFinalState,
    StNavigateToWaypoint1,
    StNavigateToWaypoint2,
    StRecoverNavigation1,
    StRecoverNavigation2,
    StRotate,
    StSetInitialPose,
)

STATE_MACHINE = SmNav2Test1

__all__ = [
    "NAV2_READY",
    "NEXT",
    "NOMINAL_TRANSITIONS",
    "STATE_MACHINE",
    "EvMaxRetriesExceeded",
    "SmNav2Test1",
    "SmNav2Test1Params",
    "StAllSensorsGo",
    "StFinalState",
    "StNavigateToWaypoint1",
    "StNavigateToWaypoint2",
    "StRecoverNavigation1",
    "StRecoverNavigation2",
    "StRotate",
    "StSetInitialPose",
]
