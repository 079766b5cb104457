"""Frontier exploration (the role of explore_lite): pick the next goal pose, remember failures, say when done.

Per call of ``next_goal``: find frontier clusters of at least ``min_frontier_size``; keep those
that known free space joins to the robot (none behind a wall); compute path distances from the
robot through cells with clearance for ``robot_radius``; give each frontier the reachable cell
nearest its middle (within ``goal_search_radius``, and ``robot_radius`` clear of unknown cells too)
as its goal; drop frontiers whose goal lies near a failed one; and return the goal of least cost. No
frontier with a reachable goal left means the exploration is complete.

The caller (a node, or a test loop) reports back: ``mark_failed(goal)`` when navigation to it
failed, and ``mark_reached(goal)`` when it arrived. A goal offered again near a reached one means
its frontier cannot be cleared from there, so it is blacklisted instead of being offered forever.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field

import numpy as np

from nav_stack.core.exploration.frontiers import Frontier, Occupancy, find_frontiers, free_mask, unknown_area
from nav_stack.core.exploration.params import ExplorerParams
from nav_stack.core.exploration.reachability import clear_of, path_distances, traversable_mask
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec


class ExplorationStatus(enum.Enum):
    """Outcome of ``Explorer.next_goal``."""

    GOAL = "goal"  # a goal was chosen
    COMPLETE = "complete"  # no reachable frontier of at least min_frontier_size remains
    NO_FREE_SPACE = "no_free_space"  # nothing within robot_radius of the robot is mapped free yet


@dataclass(frozen=True)
class ScoredFrontier:
    """A frontier with its goal pose (map frame), path distance (m), unknown area (m²) and cost."""

    frontier: Frontier
    goal: Pose2D
    distance: float
    information: float
    cost: float


@dataclass(frozen=True)
class ExplorationResult:
    """The chosen goal (None when complete) and every frontier that had a reachable goal, cheapest first."""

    status: ExplorationStatus
    goal: Pose2D | None
    candidates: list[ScoredFrontier] = field(default_factory=list)
    frontier_count: int = 0


def _near(x: float, y: float, points: list[tuple[float, float]], radius: float) -> bool:
    return any(math.hypot(x - px, y - py) <= radius for px, py in points)


class Explorer:
    """Chooses exploration goals on successive maps; holds the blacklist between calls."""

    def __init__(self, params: ExplorerParams | None = None) -> None:
        self.params = params or ExplorerParams()
        self._failed: list[tuple[float, float]] = []
        self._reached: list[tuple[float, float]] = []

    @property
    def blacklist(self) -> list[tuple[float, float]]:
        """Positions (m, map frame) of goals that will not be offered again (nor goals near them)."""
        return list(self._failed)

    def mark_failed(self, goal: Pose2D) -> None:
        """Navigation to ``goal`` failed: never offer it (or anything within blacklist_radius) again."""
        self._failed.append((goal.x, goal.y))

    def mark_reached(self, goal: Pose2D) -> None:
        """The robot arrived at ``goal``; offering it again would loop, so a repeat gets blacklisted."""
        self._reached.append((goal.x, goal.y))

    def score(self, occupancy: Occupancy, spec: GridSpec, pose: Pose2D,
              start: tuple[int, int] | None = None) -> tuple[list[ScoredFrontier], int]:
        """All frontiers with a reachable, non-blacklisted goal, cheapest first, and the frontier count.

        ``start``: the robot's :meth:`start_cell` when the caller has it already.
        """
        p = self.params
        if start is None:
            start = self.start_cell(occupancy, spec, pose)
        if start is None:
            return [], 0  # nothing mapped free around the robot: no frontier can be joined to it
        mx, my = start
        frontiers = find_frontiers(occupancy, spec, p.occupied_threshold, p.min_frontier_size)
        if not frontiers:
            return [], 0
        traversable = traversable_mask(occupancy, spec, p.robot_radius, p.occupied_threshold)
        gx, gy = spec.cell_to_world(*np.meshgrid(np.arange(spec.width), np.arange(spec.height)))
        # Free cells under the robot itself stay usable, so it can leave a spot near a wall.
        traversable |= free_mask(occupancy, p.occupied_threshold) & (
            np.hypot(gx - pose.x, gy - pose.y) <= p.robot_radius
        )
        distance = path_distances(traversable, spec, (mx, my))
        # A goal keeps robot_radius from unknown cells too: a pillar seen from one side has an unknown
        # far side, and a goal there would park the robot in it (seen: the robot sent 0.13 m from the
        # surface of turtlebot3_world's centre pillar, and wedged there).
        usable = np.isfinite(distance) & clear_of(occupancy < 0, spec, p.robot_radius)
        rx, ry, rd = gx[usable], gy[usable], distance[usable]
        # A frontier counts only if known free space joins it to the robot (not one behind a wall).
        connected = np.isfinite(path_distances(free_mask(occupancy, p.occupied_threshold), spec, (mx, my)))
        scored: list[ScoredFrontier] = []
        for frontier in frontiers:
            if not connected[frontier.cells[:, 1], frontier.cells[:, 0]].any():
                continue
            goal = self._goal_for(frontier, rx, ry, rd, pose)
            if goal is None:
                continue
            scored.append(ScoredFrontier(frontier, goal[0], goal[1], 0.0, 0.0))
        if not scored:
            return [], len(frontiers)
        info = unknown_area(
            occupancy, spec, np.array([(s.goal.x, s.goal.y) for s in scored]), p.information_radius
        )
        scored = [
            ScoredFrontier(
                s.frontier,
                s.goal,
                s.distance,
                float(a),
                p.potential_scale * s.distance
                - p.gain_scale * s.frontier.size
                - p.information_gain_scale * float(a),
            )
            for s, a in zip(scored, info, strict=True)
        ]
        scored.sort(key=lambda s: s.cost)
        return scored, len(frontiers)

    def start_cell(self, occupancy: Occupancy, spec: GridSpec, pose: Pose2D) -> tuple[int, int] | None:
        """The free cell (mx, my) the searches start from: the robot's, else the nearest within robot_radius.

        Why not always the robot's cell: SLAM can leave it unknown or mark it occupied (a robot
        parked at a wall, a map rebuilt after a loop closure), and a search started in it then
        finds no free space and every frontier looks unreachable. explore_lite starts from the
        nearest free cell for the same reason. None: no free cell within robot_radius (m) yet,
        i.e. the map has not grown around the robot. Bad inputs (shape, NaN pose, off the map) raise
        ValueError naming the value.
        """
        if occupancy.shape != spec.shape:
            raise ValueError(f"occupancy shape {occupancy.shape} does not match the grid spec {spec.shape}")
        if not all(math.isfinite(v) for v in pose):
            raise ValueError(f"robot pose must be finite, got {tuple(pose)}")
        mx, my = (int(v) for v in spec.world_to_cell(pose.x, pose.y))
        if not bool(spec.in_bounds(mx, my)):
            raise ValueError(f"robot pose ({pose.x:.2f}, {pose.y:.2f}) lies outside the map")
        free = free_mask(occupancy, self.params.occupied_threshold)
        if free[my, mx]:
            return mx, my
        reach = max(1, math.ceil(self.params.robot_radius / spec.resolution))
        x0, x1 = max(0, mx - reach), min(spec.width, mx + reach + 1)
        y0, y1 = max(0, my - reach), min(spec.height, my + reach + 1)
        ys, xs = np.nonzero(free[y0:y1, x0:x1])
        if xs.size == 0:
            return None
        cx, cy = spec.cell_to_world(xs + x0, ys + y0)
        gap = np.hypot(cx - pose.x, cy - pose.y)
        k = int(np.argmin(gap))
        if gap[k] > self.params.robot_radius:
            return None
        return int(xs[k] + x0), int(ys[k] + y0)

    def _goal_for(
        self, frontier: Frontier, rx: np.ndarray, ry: np.ndarray, rd: np.ndarray, pose: Pose2D
    ) -> tuple[Pose2D, float] | None:
        """Reachable cell nearest the frontier's middle (ties: the shorter drive), facing the frontier."""
        p = self.params
        fx, fy = frontier.middle
        gap = np.hypot(rx - fx, ry - fy)
        usable = gap <= p.goal_search_radius
        if not usable.any():
            return None
        k = int(np.argmin(np.where(usable, gap + 1e-3 * rd, np.inf)))
        x, y = float(rx[k]), float(ry[k])
        if _near(x, y, self._failed, p.blacklist_radius):
            return None  # the whole frontier is blacklisted, not just one cell of it (as explore_lite)
        yaw = (
            math.atan2(fy - y, fx - x)
            if math.hypot(fy - y, fx - x) > 1e-6
            else math.atan2(y - pose.y, x - pose.x)
        )
        return Pose2D(x, y, yaw), float(rd[k])

    def next_goal(self, occupancy: Occupancy, spec: GridSpec, pose: Pose2D) -> ExplorationResult:
        """The next exploration goal for a robot at ``pose`` (map frame), COMPLETE, or NO_FREE_SPACE
        while the map has not grown around the robot (so far nothing can be called complete)."""
        start = self.start_cell(occupancy, spec, pose)
        if start is None:
            return ExplorationResult(ExplorationStatus.NO_FREE_SPACE, None)
        while True:
            scored, count = self.score(occupancy, spec, pose, start)
            if not scored:
                return ExplorationResult(ExplorationStatus.COMPLETE, None, [], count)
            best = scored[0]
            if _near(best.goal.x, best.goal.y, self._reached, self.params.blacklist_radius):
                self.mark_failed(best.goal)  # reached before, frontier still there: it cannot be cleared
                continue
            return ExplorationResult(ExplorationStatus.GOAL, best.goal, scored, count)
