"""Robot footprint: polygon, padding, inscribed/circumscribed radii and cost checks at poses.

Why: inflation needs the inscribed radius (cells closer than it to an obstacle are certain
collisions, cost 253); controllers and behaviors need "what is the highest cost under the robot at
this pose?", often for hundreds of poses at once, so the check is vectorised over poses.

Follows nav2_costmap_2d/footprint.cpp: a round robot is a 16-gon of ``robot_radius``; padding moves
each vertex outwards by ``footprint_padding`` per axis (x += sign(x)·pad, y += sign(y)·pad); the
inscribed radius is the smallest distance from the centre to a vertex or edge, the circumscribed
radius the largest.

The cost check differs from Nav2's FootprintCollisionChecker, which scans only the outline: here
the outline is sampled every half cell and, unless ``outline_only``, the interior on a half-cell
lattice too, so a lethal cell strictly inside the robot is also seen. A pose whose samples leave
the grid costs LETHAL_OBSTACLE, as in Nav2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.params import CostmapParams
from nav_stack.core.grid import LETHAL_OBSTACLE, FloatArray, GridSpec

CostArray = npt.NDArray[np.uint8]


def _segment_distance(px: float, py: float, a: FloatArray, b: FloatArray) -> float:
    ab = b - a
    t = ((px - a[0]) * ab[0] + (py - a[1]) * ab[1]) / max(float(ab @ ab), 1e-18)
    t = min(1.0, max(0.0, t))
    return math.hypot(a[0] + t * ab[0] - px, a[1] + t * ab[1] - py)


def points_in_polygon(x: FloatArray, y: FloatArray, polygon: FloatArray) -> npt.NDArray[np.bool_]:
    """Even-odd rule test of points against a polygon ``(M, 2)``; vectorised over points."""
    inside = np.zeros(np.shape(x), dtype=bool)
    xj, yj = polygon[-1]
    for xi, yi in polygon:
        crosses = (yi > y) != (yj > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = (xj - xi) * (y - yi) / (yj - yi) + xi
        inside ^= crosses & (x < x_cross)
        xj, yj = xi, yi
    return inside


@dataclass(frozen=True)
class Footprint:
    """A padded robot polygon ``points`` (M, 2) in the robot frame (m)."""

    points: FloatArray

    def __post_init__(self) -> None:
        if self.points.ndim != 2 or self.points.shape[1] != 2 or self.points.shape[0] < 3:
            raise ValueError(f"footprint must be an (M >= 3, 2) array of points, got {self.points.shape}")
        if not np.all(np.isfinite(self.points)):
            raise ValueError(f"footprint points must be finite, got {self.points.tolist()}")

    @classmethod
    def from_radius(cls, radius: float, padding: float = 0.0) -> Footprint:
        """Nav2's round footprint: 16 points on a circle of ``radius`` (m), then padded."""
        angles = np.arange(16) * (2.0 * math.pi / 16.0)
        return cls.from_polygon(np.column_stack([radius * np.cos(angles), radius * np.sin(angles)]), padding)

    @classmethod
    def from_polygon(cls, points: npt.ArrayLike, padding: float = 0.0) -> Footprint:
        """A polygon footprint padded outwards by ``padding`` (m) along each axis."""
        pts = np.array(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ValueError(f"footprint must be a list of [x, y] points, got {np.asarray(points).tolist()}")
        return cls(pts + np.sign(pts) * padding)

    @classmethod
    def from_params(cls, params: CostmapParams) -> Footprint:
        """The footprint Costmap2DROS builds: ``footprint`` if given, else ``robot_radius``; padded."""
        if params.footprint:
            return cls.from_polygon(params.footprint, params.footprint_padding)
        return cls.from_radius(params.robot_radius, params.footprint_padding)

    @property
    def inscribed_radius(self) -> float:
        """Smallest distance (m) from the robot centre to a vertex or an edge."""
        pts = self.points
        nxt = np.roll(pts, -1, axis=0)
        vertex = float(np.min(np.hypot(pts[:, 0], pts[:, 1])))
        edges = min(_segment_distance(0.0, 0.0, a, b) for a, b in zip(pts, nxt, strict=True))
        return min(vertex, edges)

    @property
    def circumscribed_radius(self) -> float:
        """Largest distance (m) from the robot centre to a vertex."""
        return float(np.max(np.hypot(self.points[:, 0], self.points[:, 1])))

    def transformed(self, x: float, y: float, yaw: float) -> FloatArray:
        """The polygon placed at pose ``(x, y, yaw)``."""
        c, s = math.cos(yaw), math.sin(yaw)
        px, py = self.points[:, 0], self.points[:, 1]
        return np.column_stack([x + c * px - s * py, y + s * px + c * py])

    def sample_points(self, spacing: float, outline_only: bool = False) -> FloatArray:
        """Points (K, 2) in the robot frame covering the outline every ``spacing`` m (and the interior)."""
        pts = self.points
        nxt = np.roll(pts, -1, axis=0)
        samples = []
        for a, b in zip(pts, nxt, strict=True):
            n = max(1, math.ceil(math.hypot(*(b - a)) / spacing))
            t = np.arange(n, dtype=np.float64)[:, None] / n
            samples.append(a + t * (b - a))
        if not outline_only:
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            gx, gy = np.meshgrid(np.arange(lo[0], hi[0], spacing), np.arange(lo[1], hi[1], spacing))
            inside = points_in_polygon(gx.ravel(), gy.ravel(), pts)
            samples.append(np.column_stack([gx.ravel()[inside], gy.ravel()[inside]]))
            samples.append(np.zeros((1, 2)))
        return np.concatenate(samples)

    def cells_at(self, spec: GridSpec, x: float, y: float, yaw: float) -> tuple[npt.NDArray[np.int64], ...]:
        """Indices ``(my, mx)`` of the grid cells whose centres lie inside the footprint at the pose."""
        poly = self.transformed(x, y, yaw)
        mx0, my0 = spec.world_to_cell(poly[:, 0].min(), poly[:, 1].min())
        mx1, my1 = spec.world_to_cell(poly[:, 0].max(), poly[:, 1].max())
        gx, gy = np.meshgrid(np.arange(max(int(mx0), 0), min(int(mx1), spec.width - 1) + 1),
                             np.arange(max(int(my0), 0), min(int(my1), spec.height - 1) + 1))
        wx, wy = spec.cell_to_world(gx.ravel(), gy.ravel())
        inside = points_in_polygon(wx, wy, poly)
        return gy.ravel()[inside], gx.ravel()[inside]


def footprint_costs(
    costs: CostArray, spec: GridSpec, footprint: Footprint, poses: npt.ArrayLike, outline_only: bool = False
) -> CostArray:
    """Highest cost under the footprint at each pose of ``poses`` (N, 3) ``[x, y, yaw]`` → (N,) uint8."""
    pose_arr = np.atleast_2d(np.asarray(poses, dtype=np.float64))
    if pose_arr.shape[1] != 3:
        raise ValueError(f"poses must have shape (N, 3), got {pose_arr.shape}")
    samples = footprint.sample_points(spec.resolution / 2.0, outline_only)
    c, s = np.cos(pose_arr[:, 2:3]), np.sin(pose_arr[:, 2:3])
    wx = pose_arr[:, 0:1] + c * samples[:, 0] - s * samples[:, 1]
    wy = pose_arr[:, 1:2] + s * samples[:, 0] + c * samples[:, 1]
    mx, my = spec.world_to_cell(wx, wy)
    inside = spec.in_bounds(mx, my)
    values = costs[np.clip(my, 0, spec.height - 1), np.clip(mx, 0, spec.width - 1)]
    result: CostArray = values.max(axis=1)
    result[~inside.all(axis=1)] = LETHAL_OBSTACLE
    return result


def footprint_cost(
    costs: CostArray, spec: GridSpec, footprint: Footprint, x: float, y: float, yaw: float,
    outline_only: bool = False,
) -> int:
    """Highest cost (0..255) under the footprint at one pose; LETHAL_OBSTACLE when it leaves the grid."""
    return int(footprint_costs(costs, spec, footprint, [[x, y, yaw]], outline_only)[0])
