"""cl_nav2z: the Nav2 client library of SMACC2 in Python (reference/smacc2.md §3).

``ClNav2Z`` (NavigateToPose plus the behavior-server actions), components ``CpPose``,
``CpOdomTracker``, ``CpPlannerSwitcher``, ``CpGoalCheckerSwitcher``, ``CpAmcl``,
``CpWaypointNavigator`` (with its ``WaypointEventDispatcher``), ``CpWaypointsVisualizer``,
``CpSlamToolbox``, ``CpCostmapSwitch``, and the client behaviors below. Modules: ``client``, ``cp_*``
(components), ``cb_*`` (behaviors), ``service_caller`` (base of the components that call services),
``waypoints_event_dispatcher``, ``geometry``, ``odom_path`` and ``waypoints_io`` (pure helpers).
"""

from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.clients.cl_nav2z.cb_docking import CbDockRobot, CbUndockRobot
from smacc_py.clients.cl_nav2z.cb_motion import (
    CbAbsoluteRotate,
    CbNavigateBackwards,
    CbNavigateForward,
    CbRotate,
    CbRotateLookAt,
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
from smacc_py.clients.cl_nav2z.cb_retry import CbRetry
from smacc_py.clients.cl_nav2z.cb_slam import CbPauseSlam, CbResumeSlam
from smacc_py.clients.cl_nav2z.cb_waits import CbSetInitialPose, CbWaitNav2Nodes, CbWaitPose, CbWaitTransform
from smacc_py.clients.cl_nav2z.cb_waypoints import (
    CbNavigateNamedWaypoint,
    CbNavigateNextWaypointUntilReached,
    CbSeekWaypoint,
)
from smacc_py.clients.cl_nav2z.client import SERVER_LOST_CODE, ClNav2Z, is_server_lost
from smacc_py.clients.cl_nav2z.cp_amcl import CpAmcl
from smacc_py.clients.cl_nav2z.cp_costmap_switch import CpCostmapSwitch, StandardLayers
from smacc_py.clients.cl_nav2z.cp_odom_tracker import CpOdomTracker
from smacc_py.clients.cl_nav2z.cp_pose import CpPose
from smacc_py.clients.cl_nav2z.cp_slam_toolbox import CpSlamToolbox, SlamToolboxState
from smacc_py.clients.cl_nav2z.cp_switchers import CpGoalCheckerSwitcher, CpPlannerSwitcher
from smacc_py.clients.cl_nav2z.cp_waypoint_navigator import CpWaypointNavigator
from smacc_py.clients.cl_nav2z.cp_waypoints_visualizer import CpWaypointsVisualizer
from smacc_py.clients.cl_nav2z.odom_path import OdomTrackerParams, WorkingMode
from smacc_py.clients.cl_nav2z.waypoints_event_dispatcher import WaypointEventDispatcher
from smacc_py.clients.cl_nav2z.waypoints_io import Waypoint

__all__ = [
    "SERVER_LOST_CODE",
    "CbAbortNavigation",
    "CbAbsoluteRotate",
    "CbDockRobot",
    "CbNav2ZActionBase",
    "CbNavigateBackwards",
    "CbNavigateForward",
    "CbNavigateGlobalPosition",
    "CbNavigateNamedWaypoint",
    "CbNavigateNextWaypoint",
    "CbNavigateNextWaypointUntilReached",
    "CbPauseSlam",
    "CbPureSpinning",
    "CbResumeSlam",
    "CbRetry",
    "CbRotate",
    "CbRotateLookAt",
    "CbSeekWaypoint",
    "CbSetInitialPose",
    "CbSpin",
    "CbStopNavigation",
    "CbUndoPathBackwards",
    "CbUndockRobot",
    "CbWaitNav2Nodes",
    "CbWaitPose",
    "CbWaitTransform",
    "ClNav2Z",
    "CpAmcl",
    "CpCostmapSwitch",
    "CpGoalCheckerSwitcher",
    "CpOdomTracker",
    "CpPlannerSwitcher",
    "CpPose",
    "CpSlamToolbox",
    "CpWaypointNavigator",
    "CpWaypointsVisualizer",
    "OdomTrackerParams",
    "SlamToolboxState",
    "StandardLayers",
    "Waypoint",
    "WaypointEventDispatcher",
    "WorkingMode",
    "is_server_lost",
]
