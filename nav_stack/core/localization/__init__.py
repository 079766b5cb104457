"""AMCL localization (nav2_amcl semantics) in pure numpy."""

from nav_stack.core.localization.amcl import Amcl, UpdateResult, map_to_odom
from nav_stack.core.localization.clusters import PoseEstimate
from nav_stack.core.localization.params import AmclParams

__all__ = ["Amcl", "AmclParams", "PoseEstimate", "UpdateResult", "map_to_odom"]
