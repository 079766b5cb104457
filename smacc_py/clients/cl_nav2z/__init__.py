"""cl_nav2z: the Nav2 client library of SMACC2 in Python (reference/smacc2.md §3).

``ClNav2Z`` (NavigateToPose plus the behavior-server actions), components ``CpPose``,
``CpOdomTracker``, ``CpPlannerSwitcher``, ``CpGoalCheckerSwitcher``, ``CpAmcl``,
``CpWaypointNavigator``, and the client behaviors below. Modules: ``client``, ``cp_*`` (components),
``cb_*`` (behaviors), ``geometry``, ``odom_path`` and ``waypoints_io`` (pure helpers).
"""

from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.clients.cl_nav2z.cb_motion import (
    CbAbsoluteRotate,
    CbNavigateBackwards,
    CbNavigateForward,
    CbRotate,
    CbSpin,
    CbUndoPathBackwards,
)
from smacc_py.clients.cl_nav2z.cb_navigation import (
    CbAbortNavigation,
    CbNavigateGlobalPosition,
    CbNavigateNextWaypoint,
    CbStopNavigation,
)
from smacc_py.clients.cl_nav2z.cb_pure_spinning import CbPureSpinning
from smacc_py.clients.cl_nav2z.cb_waits import CbSetInitialPose, CbWaitNav2Nodes, CbWaitPose
from smacc_py.clients.cl_nav2z.client import ClNav2Z
from smacc_py.clients.cl_nav2z.cp_amcl import CpAmcl
from smacc_py.clients.cl_nav2z.cp_odom_tracker import CpOdomTracker
from smacc_py.clients.cl_nav2z.cp_pose import CpPose
from smacc_py.clients.cl_nav2z.cp_switchers import CpGoalCheckerSwitcher, CpPlannerSwitcher
from smacc_py.clients.cl_nav2z.cp_waypoint_navigator import CpWaypointNavigator
from smacc_py.clients.cl_nav2z.odom_path import OdomTrackerParams, WorkingMode
from smacc_py.clients.cl_nav2z.waypoints_io import Waypoint

__all__ = [
    "CbAbortNavigation",
    "CbAbsoluteRotate",
    "CbNav2ZActionBase",
    "CbNavigateBackwards",
    "CbNavigateForward",
    "CbNavigateGlobalPosition",
    "CbNavigateNextWaypoint",
    "CbPureSpinning",
    "CbRotate",
    "CbSetInitialPose",
    "CbSpin",
    "CbStopNavigation",
    "CbUndoPathBackwards",
    "CbWaitNav2Nodes",
    "CbWaitPose",
    "ClNav2Z",
    "CpAmcl",
    "CpGoalCheckerSwitcher",
    "CpOdomTracker",
    "CpPlannerSwitcher",
    "CpPose",
    "CpWaypointNavigator",
    "OdomTrackerParams",
    "Waypoint",
    "WorkingMode",
]
