"""Synthetic analytic worlds (wall segments + round pillars) and an exact vectorised 2D lidar for SLAM tests.

Independent of sim2d and of nav_stack's grid ray tracing on purpose: ranges come from closed-form
ray/segment and ray/circle intersections, so the SLAM under test never meets scans produced by its
own rasterisation. The world also rasterises itself (ground-truth occupancy, free space) so tests
can compare maps cell by cell, and plans ground-truth paths for "teleporting" a robot along them.
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D, normalize_angle
from nav_stack.core.grid import GridSpec


@dataclass(frozen=True)
class World:
    """Walls as segments ``(x0, y0, x1, y1)`` and pillars as circles ``(cx, cy, r)`` (m)."""

    segments: np.ndarray
    circles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    def cast(self, x: float, y: float, angles: np.ndarray, range_max: float) -> np.ndarray:
        """Distance (m) from ``(x, y)`` along world-frame ``angles`` to the first surface; inf if none."""
        dx, dy = np.cos(angles)[:, None], np.sin(angles)[:, None]
        best = np.full(len(angles), np.inf)
        if len(self.segments):
            ax, ay, bx, by = (self.segments[:, k][None, :] for k in range(4))
            ex, ey = bx - ax, by - ay
            denom = dx * ey - dy * ex
            with np.errstate(divide="ignore", invalid="ignore"):
                t = ((ax - x) * ey - (ay - y) * ex) / denom
                u = ((ax - x) * dy - (ay - y) * dx) / denom
            ok = (np.abs(denom) > 1e-12) & (t > 1e-9) & (u >= 0.0) & (u <= 1.0)
            best = np.minimum(best, np.where(ok, t, np.inf).min(axis=1))
        if len(self.circles):
            cx, cy, r = (self.circles[:, k][None, :] for k in range(3))
            fx, fy = x - cx, y - cy
            b = fx * dx + fy * dy
            c = fx * fx + fy * fy - r * r
            disc = b * b - c
            with np.errstate(invalid="ignore"):
                t = -b - np.sqrt(disc)
            ok = (disc >= 0.0) & (t > 1e-9)
            best = np.minimum(best, np.where(ok, t, np.inf).min(axis=1))
        return np.where(best <= range_max, best, np.inf)

    def scan(
        self,
        pose: Pose2D,
        beams: int = 360,
        range_min: float = 0.12,
        range_max: float = 3.5,
        noise_std: float = 0.0,
        rng: np.random.Generator | None = None,
    ) -> LaserScan:
        """An LDS-01-like scan (0..2π, +inf for no return) from a sensor at ``pose``."""
        increment = 2.0 * math.pi / beams
        local = np.arange(beams) * increment
        ranges = self.cast(pose.x, pose.y, pose.yaw + local, range_max)
        if noise_std > 0.0:
            if rng is None:
                raise ValueError("noise_std > 0 needs an rng")
            finite = np.isfinite(ranges)
            ranges[finite] += rng.normal(0.0, noise_std, int(finite.sum()))
        return LaserScan(ranges, 0.0, increment, range_min, range_max)

    def occupied_mask(self, spec: GridSpec) -> np.ndarray:
        """Cells whose centre lies within half a cell of a wall or pillar surface."""
        gx, gy = self._centres(spec)
        return self._surface_distance(gx, gy) <= spec.resolution * 0.5 + 1e-6

    def free_mask(self, spec: GridSpec, inside: tuple[float, float], clearance: float = 0.0) -> np.ndarray:
        """Cells reachable from ``inside`` whose centre is over ``clearance`` + one cell from any surface.

        One full cell (not half) keeps the 4-connected flood from leaking between two cells a wall
        passes exactly between.
        """
        gx, gy = self._centres(spec)
        open_ = self._surface_distance(gx, gy) > clearance + spec.resolution
        open_ &= ~self._inside_pillar(gx, gy)
        mx, my = spec.world_to_cell(inside[0], inside[1])
        return _flood(open_, int(my), int(mx))

    def path(
        self, spec: GridSpec, start: Pose2D, goal: Pose2D, clearance: float, strict: bool = False
    ) -> list[Pose2D]:
        """Ground-truth 8-connected BFS path (cell centres) from start to goal through cells with clearance.

        An unreachable goal gives ``[start, goal]`` (a straight jump), or ``[]`` when ``strict``: a
        goal the SLAM placed off the map, or inside a wall, when its map is wrong.
        """
        gx, gy = self._centres(spec)
        open_ = self._surface_distance(gx, gy) > clearance
        s, g = _row_col(spec, start), _row_col(spec, goal)
        if strict and not (0 <= g[0] < spec.height and 0 <= g[1] < spec.width and open_[g]):
            return []
        open_[s] = open_[g] = True
        parent: dict[tuple[int, int], tuple[int, int]] = {s: s}
        queue = deque([s])
        while queue and g not in parent:
            r, c = queue.popleft()
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)):
                n = (r + dr, c + dc)
                if 0 <= n[0] < spec.height and 0 <= n[1] < spec.width and open_[n] and n not in parent:
                    parent[n] = (r, c)
                    queue.append(n)
        if g not in parent:
            return [] if strict else [start, goal]
        cells = [g]
        while cells[-1] != s:
            cells.append(parent[cells[-1]])
        xs, ys = spec.cell_to_world(
            np.array([c for _, c in cells[::-1]]), np.array([r for r, _ in cells[::-1]])
        )
        return (
            [start]
            + [Pose2D(float(a), float(b), 0.0) for a, b in zip(xs[1:-1], ys[1:-1], strict=True)]
            + [goal]
        )

    def _centres(self, spec: GridSpec) -> tuple[np.ndarray, np.ndarray]:
        mx, my = np.meshgrid(np.arange(spec.width), np.arange(spec.height))
        return spec.cell_to_world(mx, my)

    def _surface_distance(self, gx: np.ndarray, gy: np.ndarray) -> np.ndarray:
        d = np.full(gx.shape, np.inf)
        for x0, y0, x1, y1 in self.segments:
            ex, ey = x1 - x0, y1 - y0
            t = np.clip(((gx - x0) * ex + (gy - y0) * ey) / (ex * ex + ey * ey), 0.0, 1.0)
            d = np.minimum(d, np.hypot(gx - x0 - t * ex, gy - y0 - t * ey))
        for cx, cy, r in self.circles:
            d = np.minimum(d, np.abs(np.hypot(gx - cx, gy - cy) - r))
        return d

    def _inside_pillar(self, gx: np.ndarray, gy: np.ndarray) -> np.ndarray:
        inside = np.zeros(gx.shape, dtype=bool)
        for cx, cy, r in self.circles:
            inside |= np.hypot(gx - cx, gy - cy) < r
        return inside


def _row_col(spec: GridSpec, pose: Pose2D) -> tuple[int, int]:
    """The (row, column) index of the cell holding ``pose``, the order a numpy grid is indexed in."""
    mx, my = spec.world_to_cell(pose.x, pose.y)
    return int(my), int(mx)


def _flood(open_: np.ndarray, r0: int, c0: int) -> np.ndarray:
    """4-connected flood fill of ``open_`` from (r0, c0)."""
    out = np.zeros_like(open_)
    if not open_[r0, c0]:
        return out
    out[r0, c0] = True
    queue = deque([(r0, c0)])
    h, w = open_.shape
    while queue:
        r, c = queue.popleft()
        for n in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= n[0] < h and 0 <= n[1] < w and open_[n] and not out[n]:
                out[n] = True
                queue.append(n)
    return out


def _polygon_segments(vertices: list[tuple[float, float]]) -> np.ndarray:
    return np.array([(*vertices[i], *vertices[(i + 1) % len(vertices)]) for i in range(len(vertices))])


def hexagon_world() -> World:
    """TB3-world-like room: inner hexagon (±2.933, 0), (±1.466, ±2.54) with five pillars r 0.15 m."""
    hexagon = [(2.933, 0.0), (1.466, 2.54), (-1.466, 2.54), (-2.933, 0.0), (-1.466, -2.54), (1.466, -2.54)]
    pillars = np.array(
        [(-1.1, -1.1, 0.15), (1.1, -1.1, 0.15), (0.0, 0.0, 0.15), (-1.1, 1.1, 0.15), (1.1, 1.1, 0.15)]
    )
    return World(_polygon_segments(hexagon), pillars)


def ring_world() -> World:
    """A square ring corridor (outer 10 m, inner block 7 m, corridor 1.5 m wide) with pillars and niches.

    Larger than the lidar range, so scan matching alone drifts along the corridors and only a
    loop closure can bring the robot back onto its start.
    """
    outer = _polygon_segments([(-5.0, -5.0), (5.0, -5.0), (5.0, 5.0), (-5.0, 5.0)])
    inner = _polygon_segments([(-3.5, -3.5), (3.5, -3.5), (3.5, 3.5), (-3.5, 3.5)])
    pillars = np.array(
        [
            (-4.6, -1.0, 0.12),
            (0.5, -4.6, 0.12),
            (4.6, 1.5, 0.12),
            (-1.5, 4.6, 0.12),
            (-4.0, 2.5, 0.1),
            (2.5, -4.0, 0.1),
            (4.0, -2.0, 0.1),
            (1.0, 4.0, 0.1),
        ]
    )
    return World(np.vstack([outer, inner]), pillars)


def _wall(
    x0: float, y0: float, x1: float, y1: float, gaps: tuple[tuple[float, float], ...] = ()
) -> np.ndarray:
    """An axis-aligned wall from (x0, y0) to (x1, y1) (m) as segments, with door ``gaps``.

    Each gap ``(a, b)`` is an interval of the varying coordinate (x for a horizontal wall, y for a
    vertical one) left open; the wall is split around it.
    """
    horizontal = y0 == y1
    if not horizontal and x0 != x1:
        raise ValueError("_wall builds axis-aligned walls only")
    lo, hi = (min(x0, x1), max(x0, x1)) if horizontal else (min(y0, y1), max(y0, y1))
    cuts = [lo]
    for a, b in sorted(gaps):
        cuts += [a, b]
    cuts.append(hi)
    pieces = [(a, b) for a, b in zip(cuts[::2], cuts[1::2], strict=True) if b - a > 1e-9]
    if horizontal:
        return np.array([(a, y0, b, y0) for a, b in pieces]).reshape(-1, 4)
    return np.array([(x0, a, x0, b) for a, b in pieces]).reshape(-1, 4)


def _box(x0: float, y0: float, x1: float, y1: float, open_side: str) -> np.ndarray:
    """Three walls of the rectangle (x0, y0)-(x1, y1) (m): a niche or side room whose ``open_side``
    ("n", "s", "e" or "w") lies on the corridor wall it opens from."""
    sides = {
        "s": (x0, y0, x1, y0),
        "n": (x0, y1, x1, y1),
        "w": (x0, y0, x0, y1),
        "e": (x1, y0, x1, y1),
    }
    return np.array([seg for side, seg in sides.items() if side != open_side])


def office_world() -> World:
    """An office floor 14 x 10 m (x -7..7, y -5..5): corridors around two blocks of two rooms each.

    Why: the ring has one loop; here the robot can close three (around the west block, around the
    east block, around both) through a 2 m central corridor and 1.5 m outer corridors, each longer
    than the lidar range. The four rooms (4.5 x 3.5 m, 0.9 m doors on different corridors) must be
    explored through their doors, so their walls are seen from both sides, and the doors and two
    corridor pillars are the only features along the 7 m side corridors.
    """
    walls = [
        _polygon_segments([(-7.0, -5.0), (7.0, -5.0), (7.0, 5.0), (-7.0, 5.0)]),
        # west block x -5.5..-1: north room (door north), south room (door to the central corridor)
        _wall(-5.5, 3.5, -1.0, 3.5, gaps=((-3.7, -2.8),)),
        _wall(-5.5, -3.5, -1.0, -3.5),
        _wall(-5.5, -3.5, -5.5, 3.5),
        _wall(-1.0, -3.5, -1.0, 3.5, gaps=((-2.2, -1.3),)),
        _wall(-5.5, 0.0, -1.0, 0.0),
        # east block x 1..5.5: north room (door to the central corridor), south room (door south)
        _wall(1.0, 3.5, 5.5, 3.5),
        _wall(1.0, -3.5, 5.5, -3.5, gaps=((2.8, 3.7),)),
        _wall(5.5, -3.5, 5.5, 3.5),
        _wall(1.0, -3.5, 1.0, 3.5, gaps=((1.3, 2.2),)),
        _wall(1.0, 0.0, 5.5, 0.0),
    ]
    pillars = np.array(
        [
            (-6.6, 0.8, 0.12),  # west corridor
            (6.6, -1.2, 0.12),  # east corridor
            (-3.2, -1.8, 0.15),  # a column in each room
            (-4.0, 2.0, 0.15),
            (3.5, 1.6, 0.15),
            (2.6, -1.6, 0.15),
        ]
    )
    return World(np.vstack(walls), pillars)


def large_loop_world() -> World:
    """A 24 x 24 m square corridor ring (outer walls x, y -12..12, inner block -10..10, 2 m wide),
    with a side room north (x -3..1, y 12..15), two niches and five pillars: 26 x 27 m in all.

    Why: one lap is 88 m, so odometry and scan-matching drift pile up for a long way before the
    first loop closure, and the closure must be found within a wide pose-graph uncertainty. The
    features are sparse on purpose: stretches of up to 5 m where the lidar (3.5 m) sees only two
    parallel walls leave the pose along the corridor to odometry and the matcher's prior, a fair
    but hard test of closing a loop rather than of scan matching.
    """
    walls = [
        # outer wall, with the side room's door (north), a niche (west)
        _wall(-12.0, -12.0, 12.0, -12.0),
        _wall(12.0, -12.0, 12.0, 12.0),
        _wall(-12.0, 12.0, 12.0, 12.0, gaps=((-1.5, -0.6),)),
        _wall(-12.0, -12.0, -12.0, 12.0, gaps=((-1.0, 1.0),)),
        _box(-3.0, 12.0, 1.0, 15.0, open_side="s"),
        _box(-13.0, -1.0, -12.0, 1.0, open_side="e"),
        # inner block, with a niche cut into its south side
        _wall(-10.0, -10.0, 10.0, -10.0, gaps=((-1.0, 1.0),)),
        _box(-1.0, -10.0, 1.0, -9.0, open_side="s"),
        _wall(10.0, -10.0, 10.0, 10.0),
        _wall(-10.0, 10.0, 10.0, 10.0),
        _wall(-10.0, -10.0, -10.0, 10.0),
    ]
    pillars = np.array(
        [
            (6.0, -11.6, 0.12),  # south corridor
            (11.6, -3.0, 0.12),  # east corridor
            (10.4, 4.0, 0.12),
            (5.0, 10.4, 0.12),  # north corridor
            (-10.4, 6.0, 0.12),  # west corridor
        ]
    )
    return World(np.vstack(walls), pillars)


@dataclass
class NoisyOdometry:
    """Wheel odometry that integrates true motion increments with scale and heading drift (seeded)."""

    rng: np.random.Generator
    translation_noise: float = 0.02  # relative std of each translation increment
    rotation_noise: float = 0.02  # rad of heading noise per metre travelled
    rotation_bias: float = 0.0  # rad of systematic heading drift per metre travelled
    pose: Pose2D = field(default_factory=lambda: Pose2D(0.0, 0.0, 0.0))
    _last_true: Pose2D | None = None

    def update(self, true_pose: Pose2D) -> Pose2D:
        """Advance with the motion from the previous true pose to ``true_pose``; return the odom pose."""
        if self._last_true is None:
            self._last_true = true_pose
            return self.pose
        p = self._last_true
        c, s = math.cos(p.yaw), math.sin(p.yaw)
        dx, dy = true_pose.x - p.x, true_pose.y - p.y
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        dyaw = normalize_angle(true_pose.yaw - p.yaw)
        dist = math.hypot(lx, ly)
        scale = 1.0 + self.rng.normal(0.0, self.translation_noise)
        dyaw += self.rng.normal(0.0, self.rotation_noise * max(dist, 0.05)) + self.rotation_bias * dist
        o = self.pose
        co, so = math.cos(o.yaw), math.sin(o.yaw)
        self.pose = Pose2D(
            o.x + scale * (co * lx - so * ly),
            o.y + scale * (so * lx + co * ly),
            normalize_angle(o.yaw + dyaw),
        )
        self._last_true = true_pose
        return self.pose


def interpolate(waypoints: list[Pose2D], step: float, turn_step: float = 0.15) -> list[Pose2D]:
    """Poses every ``step`` m along the polyline, facing the direction of travel, turning in place first."""
    out = [waypoints[0]]
    for a, b in itertools.pairwise(waypoints):
        length = math.hypot(b.x - a.x, b.y - a.y)
        if length < 1e-9:
            continue
        heading = math.atan2(b.y - a.y, b.x - a.x)
        turn = normalize_angle(heading - out[-1].yaw)
        for _ in range(int(abs(turn) / turn_step)):
            out.append(Pose2D(a.x, a.y, normalize_angle(out[-1].yaw + math.copysign(turn_step, turn))))
        out.append(Pose2D(a.x, a.y, heading))
        n = max(1, math.ceil(length / step))
        for k in range(1, n + 1):
            f = k / n
            out.append(Pose2D(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), heading))
    return out


def dilate(mask: np.ndarray) -> np.ndarray:
    """One-cell (8-neighbour) binary dilation."""
    out = mask.copy()
    padded = np.pad(mask, 1)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            out |= padded[1 + dr : 1 + dr + mask.shape[0], 1 + dc : 1 + dc + mask.shape[1]]
    return out


def iou_dilated(estimate: np.ndarray, truth: np.ndarray) -> float:
    """IoU with a one-cell tolerance: TP = estimate cells within one cell of truth, FP = the other
    estimate cells, FN = truth cells farther than one cell from any estimate cell."""
    tp = int((estimate & dilate(truth)).sum())
    fp = int((estimate & ~dilate(truth)).sum())
    fn = int((truth & ~dilate(estimate)).sum())
    return tp / max(1, tp + fp + fn)


def resample_to(values: np.ndarray, spec: GridSpec, target: GridSpec, fill: int) -> np.ndarray:
    """Copy a grid onto ``target``'s cells (same resolution, axis-aligned), filling the rest with ``fill``."""
    out = np.full(target.shape, fill, dtype=values.dtype)
    ox = round((spec.origin_x - target.origin_x) / target.resolution)
    oy = round((spec.origin_y - target.origin_y) / target.resolution)
    r0, c0 = max(0, oy), max(0, ox)
    r1, c1 = min(target.height, oy + spec.height), min(target.width, ox + spec.width)
    if r1 > r0 and c1 > c0:
        out[r0:r1, c0:c1] = values[r0 - oy : r1 - oy, c0 - ox : c1 - ox]
    return out
