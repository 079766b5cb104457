"""What this stack can run: its Nav2 servers, and the plugin types each server accepts.

Why one catalog: nav-bringup checks a user's parameter files against it before it starts anything
(nav_stack/ros/bringup/config_check.py), and the servers' plugin factories refuse the same types at
configure, so the two can never disagree about what is supported. Names are Nav2's class names
without the package (``nav2_mppi_controller::MPPIController`` → ``MPPIController``); Humble's
``pkg/Class`` spelling is accepted too.

Pure: standard library only.
"""

from __future__ import annotations

from dataclasses import dataclass

#: nav2_bringup's lifecycle lists (Jazzy's localization_launch.py and navigation_launch.py), in order.
LOCALIZATION_NODES = ("map_server", "amcl")
NAVIGATION_NODES = ("controller_server", "smoother_server", "planner_server", "behavior_server",
                    "velocity_smoother", "collision_monitor", "bt_navigator", "waypoint_follower",
                    "docking_server")
#: Servers nav-bringup runs only when a parameter file configures them (their section exists);
#: the others it always runs, as Nav2's launch files do.
OPTIONAL_NODES = frozenset({"smoother_server", "velocity_smoother", "collision_monitor", "docking_server"})

#: The servers this stack has (grows as servers are added).
AVAILABLE_NODES = frozenset({"map_server", "amcl", "controller_server", "smoother_server", "planner_server",
                             "behavior_server", "velocity_smoother", "collision_monitor", "bt_navigator",
                             "waypoint_follower", "docking_server"})

#: Nav2 nodes a parameter file may configure that nav-bringup never starts: they are left alone,
#: with a note in the log (Nav2's own file configures several of them for other launch files).
NOT_LAUNCHED = {
    "route_server": "nav2_route is not part of this stack; the default trees do not use it",
    "loopback_simulator": "the simulator is sim2d",
    "robot_state_publisher": "sim2d publishes the robot's static transforms",
    "map_saver": "map_saver runs with `nav-bringup --slam` and `nav-map-saver`",
    "slam": "runs with `nav-bringup --slam`",
    "slam_toolbox": "runs with `nav-bringup --slam`",
    "bt_navigator_navigate_to_pose_rclcpp_node": "a helper node of Nav2's C++ BT navigator",
    "bt_navigator_navigate_through_poses_rclcpp_node": "a helper node of Nav2's C++ BT navigator",
}


@dataclass(frozen=True)
class PluginList:
    """A server parameter that lists plugin ids, each typed by ``<id>.plugin``.

    Attributes:
        node: the server's node name (fully qualified, without the leading '/').
        key: the list parameter (``controller_plugins``), or a single id (``waypoint_task_executor_plugin``).
        default: the ids the server uses when the file does not set ``key``.
        supported: the class names it accepts.
        default_types: the type of an id whose ``<id>.plugin`` the file leaves out.
        type_key: the parameter under the id that names its type.
    """

    node: str
    key: str
    default: tuple[str, ...]
    supported: tuple[str, ...]
    default_types: tuple[tuple[str, str], ...] = ()
    type_key: str = "plugin"


CONTROLLERS = ("DWBLocalPlanner", "RegulatedPurePursuitController", "RotationShimController",
               "MPPIController")
GOAL_CHECKERS = ("SimpleGoalChecker", "StoppedGoalChecker")
PROGRESS_CHECKERS = ("SimpleProgressChecker",)
PLANNERS = ("NavfnPlanner", "ThetaStarPlanner")
BEHAVIORS = ("Spin", "BackUp", "DriveOnHeading", "Wait", "AssistedTeleop")
SMOOTHERS = ("SimpleSmoother",)
COSTMAP_LAYERS = ("StaticLayer", "ObstacleLayer", "VoxelLayer", "InflationLayer")
NAVIGATORS = ("NavigateToPoseNavigator", "NavigateThroughPosesNavigator")
WAYPOINT_TASK_EXECUTORS = ("WaitAtWaypoint",)
AMCL_MOTION_MODELS = ("DifferentialMotionModel", "OmniMotionModel")
DOCKS = ("SimpleChargingDock", "SimpleNonChargingDock")
COLLISION_POLYGONS = ("polygon", "circle")

_LAYER_DEFAULTS = (("static_layer", "StaticLayer"), ("obstacle_layer", "ObstacleLayer"),
                   ("voxel_layer", "VoxelLayer"), ("inflation_layer", "InflationLayer"))

PLUGIN_LISTS: tuple[PluginList, ...] = (
    PluginList("controller_server", "controller_plugins", ("FollowPath",), CONTROLLERS,
               (("FollowPath", "DWBLocalPlanner"), ("DWB", "DWBLocalPlanner"),
                ("RPP", "RegulatedPurePursuitController"), ("RotationShim", "RotationShimController"),
                ("MPPI", "MPPIController"))),
    PluginList("controller_server", "goal_checker_plugins", ("general_goal_checker",), GOAL_CHECKERS,
               (("general_goal_checker", "SimpleGoalChecker"), ("goal_checker", "SimpleGoalChecker"),
                ("stopped_goal_checker", "StoppedGoalChecker"))),
    PluginList("controller_server", "progress_checker_plugins", ("progress_checker",), PROGRESS_CHECKERS,
               (("progress_checker", "SimpleProgressChecker"),)),
    PluginList("planner_server", "planner_plugins", ("GridBased",), PLANNERS,
               (("GridBased", "NavfnPlanner"), ("ThetaStar", "ThetaStarPlanner"))),
    PluginList("behavior_server", "behavior_plugins", ("spin", "backup", "drive_on_heading", "wait"),
               BEHAVIORS,
               (("spin", "Spin"), ("backup", "BackUp"), ("drive_on_heading", "DriveOnHeading"),
                ("assisted_teleop", "AssistedTeleop"), ("wait", "Wait"))),
    PluginList("smoother_server", "smoother_plugins", ("simple_smoother",), SMOOTHERS,
               (("simple_smoother", "SimpleSmoother"),)),
    PluginList("local_costmap/local_costmap", "plugins", ("obstacle_layer", "inflation_layer"),
               COSTMAP_LAYERS, _LAYER_DEFAULTS),
    PluginList("global_costmap/global_costmap", "plugins",
               ("static_layer", "obstacle_layer", "inflation_layer"), COSTMAP_LAYERS, _LAYER_DEFAULTS),
    PluginList("bt_navigator", "navigators", ("navigate_to_pose", "navigate_through_poses"), NAVIGATORS,
               (("navigate_to_pose", "NavigateToPoseNavigator"),
                ("navigate_through_poses", "NavigateThroughPosesNavigator"))),
    PluginList("docking_server", "dock_plugins", (), DOCKS),
    PluginList("collision_monitor", "polygons", (), COLLISION_POLYGONS, type_key="type"),
    PluginList("waypoint_follower", "waypoint_task_executor_plugin", ("wait_at_waypoint",),
               WAYPOINT_TASK_EXECUTORS, (("wait_at_waypoint", "WaitAtWaypoint"),)),
)

#: Single-valued type parameters: (node, key, default, supported).
TYPE_PARAMETERS: tuple[tuple[str, str, str, tuple[str, ...]], ...] = (
    ("amcl", "robot_model_type", "nav2_amcl::DifferentialMotionModel", AMCL_MOTION_MODELS),
)


def class_name(plugin_type: str) -> str:
    """``nav2_mppi_controller::MPPIController`` (or Humble's ``pkg/Class``) → ``MPPIController``."""
    return str(plugin_type).replace("/", "::").split("::")[-1]
