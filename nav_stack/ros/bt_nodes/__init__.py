"""ROS-backed behaviour-tree leaves for bt_navigator (Nav2's nav2_behavior_tree plugins, in Python).

``register_ros_nodes(factory, ros)`` adds ComputePathToPose, ComputePathThroughPoses, FollowPath,
Spin, BackUp, DriveOnHeading, Wait, ClearEntireCostmap and RemovePassedGoals to a core
``BehaviorTreeFactory``; ``SelectorTopics`` feeds the core selectors from their topics.
"""

from __future__ import annotations

from nav_stack.core.bt import BehaviorTreeFactory, TreeNode
from nav_stack.ros.bt_nodes.actions import (
    BackUpAction,
    ComputePathThroughPosesAction,
    ComputePathToPoseAction,
    DriveOnHeadingAction,
    FollowPathAction,
    SpinAction,
    WaitAction,
)
from nav_stack.ros.bt_nodes.conditions import RemovePassedGoals, SelectorTopics
from nav_stack.ros.bt_nodes.context import BtRosContext, LeafFailure, code_name
from nav_stack.ros.bt_nodes.docking import DockRobotAction, UndockRobotAction
from nav_stack.ros.bt_nodes.services import ClearEntireCostmapService
from nav_stack.ros.bt_nodes.smooth_path import SmoothPathAction

#: Nav2 BT node id -> leaf class
ROS_LEAVES: dict[str, type[TreeNode]] = {
    "ComputePathToPose": ComputePathToPoseAction,
    "ComputePathThroughPoses": ComputePathThroughPosesAction,
    "FollowPath": FollowPathAction,
    "SmoothPath": SmoothPathAction,
    "Spin": SpinAction,
    "BackUp": BackUpAction,
    "DriveOnHeading": DriveOnHeadingAction,
    "Wait": WaitAction,
    "ClearEntireCostmap": ClearEntireCostmapService,
    "RemovePassedGoals": RemovePassedGoals,
    "DockRobot": DockRobotAction,
    "UndockRobot": UndockRobotAction,
}


def register_ros_nodes(factory: BehaviorTreeFactory, ros: BtRosContext) -> None:
    """Register every ROS-backed leaf under its Nav2 id; each instance gets ``ros``."""
    for node_id, node_type in ROS_LEAVES.items():
        factory.register(node_id, node_type, ros=ros)


__all__ = ["ROS_LEAVES", "BtRosContext", "LeafFailure", "SelectorTopics", "code_name", "register_ros_nodes"]
