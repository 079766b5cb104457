"""Frontier exploration (pure numpy): find frontiers on a SLAM map, score them, choose goals.

Typical use (an exploration node, each time the robot is idle)::

    explorer = Explorer(ExplorerParams(robot_radius=0.22))
    result = explorer.next_goal(occupancy, spec, robot_pose)
    if result.status is ExplorationStatus.COMPLETE: ...        # done
    elif result.status is ExplorationStatus.NO_FREE_SPACE: ... # wait for SLAM to map around the robot
    else: navigate to result.goal; explorer.mark_reached(goal) or explorer.mark_failed(goal)
"""

from nav_stack.core.exploration.explorer import ExplorationResult, ExplorationStatus, Explorer, ScoredFrontier
from nav_stack.core.exploration.frontiers import (
    Frontier,
    find_frontiers,
    frontier_mask,
    label_clusters,
    unknown_area,
)
from nav_stack.core.exploration.params import ExplorerParams
from nav_stack.core.exploration.reachability import path_distances, traversable_mask

__all__ = [
    "ExplorationResult",
    "ExplorationStatus",
    "Explorer",
    "ExplorerParams",
    "Frontier",
    "ScoredFrontier",
    "find_frontiers",
    "frontier_mask",
    "label_clusters",
    "path_distances",
    "traversable_mask",
    "unknown_area",
]
