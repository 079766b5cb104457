"""Parameters of frontier exploration, named after explore_lite (m-explore) where it has the knob."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields


@dataclass(frozen=True)
class ExplorerParams:
    """Frontier exploration knobs (SI units: m, m²).

    A frontier's cost is ``potential_scale · path_distance − gain_scale · size −
    information_gain_scale · unknown_area``; the cheapest reachable frontier becomes the goal.

    Attributes:
        robot_radius: goals keep at least this clearance (m) from occupied cells (TB3 waffle 0.22).
        occupied_threshold: occupancy values at or above this are obstacles (map_server trinary: 100).
        min_frontier_size: frontiers shorter than this (m, cells × resolution) are ignored.
        potential_scale: weight of the path distance (m) from the robot through free space.
        gain_scale: weight of the frontier size (m).
        information_gain_scale: weight of the unknown area (m²) within ``information_radius`` of the goal.
        information_radius: half side (m) of the square counted as the goal's information gain.
        goal_search_radius: a goal cell must lie within this distance (m) of its frontier.
        blacklist_radius: goals within this distance (m) of a failed goal are not offered again.
    """

    robot_radius: float = 0.22
    occupied_threshold: int = 65
    min_frontier_size: float = 0.5
    potential_scale: float = 3.0
    gain_scale: float = 1.0
    information_gain_scale: float = 1.0
    information_radius: float = 1.0
    goal_search_radius: float = 1.5
    blacklist_radius: float = 0.3

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"ExplorerParams.{f.name} must be a finite number >= 0, got {value}")
        if not 1 <= self.occupied_threshold <= 100:
            raise ValueError(
                f"ExplorerParams.occupied_threshold must lie in 1..100, got {self.occupied_threshold}"
            )
