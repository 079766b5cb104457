"""Static 2D geometry of a world: circles, axis-aligned boxes and convex polygons, in the map frame.

Why one container: the same obstacles feed three consumers that must agree exactly: pymunk shapes
for collisions (sim2d.core.collision), line segments for vectorised lidar ray casting
(sim2d.core.lidar) and point-in-obstacle tests for map rasterisation (sim2d.core.rasterize).
All coordinates are metres in the world (= map) frame; angles are radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


def normalize_angle(angle: float) -> float:
    """Wrap an angle to [-π, π) (rad); sim2d's own copy, kept independent of nav_stack."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def regular_polygon(center: tuple[float, float], circumradius: float, sides: int,
                    rotation: float = 0.0) -> FloatArray:
    """Vertices (sides, 2) of a regular polygon, counter-clockwise, first vertex at ``rotation`` (rad)."""
    angles = rotation + 2.0 * math.pi * np.arange(sides) / sides
    return np.column_stack((center[0] + circumradius * np.cos(angles),
                            center[1] + circumradius * np.sin(angles)))


def is_convex_ccw(vertices: FloatArray) -> bool:
    """True when the polygon (k, 2) is strictly convex and counter-clockwise."""
    edges = np.roll(vertices, -1, axis=0) - vertices
    nxt = np.roll(edges, -1, axis=0)
    cross = edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0]
    return bool(len(vertices) >= 3 and np.all(cross > 1e-12))


def ring_pieces(inner: FloatArray, thickness: float) -> list[FloatArray]:
    """Split a wall of ``thickness`` (m) outside a convex CCW polygon into mitred convex quads.

    Why quads: pymunk polygons must be convex, and a mitred piece per side leaves no gap at the
    corners, so the wall is solid from inside and out.
    """
    k = len(inner)
    edges = np.roll(inner, -1, axis=0) - inner
    normals = np.column_stack((edges[:, 1], -edges[:, 0])) / np.linalg.norm(edges, axis=1)[:, None]
    outer = np.empty_like(inner)
    for i in range(k):  # one miter per vertex: intersection of the two offset side lines
        n_prev, n_next = normals[i - 1], normals[i]
        bisector = n_prev + n_next
        outer[i] = inner[i] + bisector * thickness / float(np.dot(bisector, n_next))
    return [np.array([inner[i], outer[i], outer[(i + 1) % k], inner[(i + 1) % k]])
            for i in range(k)]


def points_in_convex(points: FloatArray, vertices: FloatArray) -> BoolArray:
    """Which points (P, 2) lie inside a convex CCW polygon (k, 2)."""
    edges = np.roll(vertices, -1, axis=0) - vertices
    rel = points[:, None, :] - vertices[None, :, :]
    cross = edges[None, :, 0] * rel[:, :, 1] - edges[None, :, 1] * rel[:, :, 0]
    result: BoolArray = np.all(cross >= 0.0, axis=1)
    return result


def _segment_distance(points: FloatArray, segments: FloatArray) -> FloatArray:
    """Distance (P,) from each point to the nearest of the segments (N, 4) [x0, y0, x1, y1]."""
    if len(segments) == 0:
        return np.full(len(points), np.inf)
    p0 = segments[None, :, 0:2]
    d = segments[None, :, 2:4] - p0
    rel = points[:, None, :] - p0
    length2 = np.maximum(np.sum(d * d, axis=2), 1e-18)
    t = np.clip(np.sum(rel * d, axis=2) / length2, 0.0, 1.0)
    closest = rel - t[:, :, None] * d
    result: FloatArray = np.sqrt(np.min(np.sum(closest * closest, axis=2), axis=1))
    return result


def polygon_edges(vertices: FloatArray) -> FloatArray:
    """Edges (k, 4) [x0, y0, x1, y1] of a closed polygon (k, 2)."""
    return np.hstack((vertices, np.roll(vertices, -1, axis=0)))


def box_edges(boxes: FloatArray) -> FloatArray:
    """Edges (4K, 4) of axis-aligned boxes (K, 4) [xmin, ymin, xmax, ymax]."""
    x0, y0, x1, y1 = boxes.T
    return np.concatenate([np.column_stack(c) for c in (
        (x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0))])


@dataclass(frozen=True)
class StaticGeometry:
    """Every static obstacle of a world.

    Attributes:
        circles: (M, 3) [cx, cy, r] (m).
        boxes: (K, 4) axis-aligned boxes [xmin, ymin, xmax, ymax] (m); map worlds use these.
        polygons: convex counter-clockwise polygons, each (k, 2) (m).
        segments: (N, 4) [x0, y0, x1, y1] that a lidar beam can hit, oriented with the obstacle on
            their left. Defaults to every polygon and box edge; map worlds pass only the
            occupied/free boundary, which is far shorter.
    """

    circles: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    boxes: FloatArray = field(default_factory=lambda: np.zeros((0, 4)))
    polygons: tuple[FloatArray, ...] = ()
    segments: FloatArray | None = None

    def __post_init__(self) -> None:
        if self.segments is None:
            parts = [polygon_edges(p) for p in self.polygons] + [box_edges(self.boxes)]
            object.__setattr__(self, "segments", np.concatenate(parts) if parts else np.zeros((0, 4)))

    @property
    def ray_segments(self) -> FloatArray:
        """Segments (N, 4) for ray casting (never None after construction)."""
        assert self.segments is not None
        return self.segments

    def with_polygons(self, polygons: tuple[FloatArray, ...]) -> StaticGeometry:
        """This geometry plus convex CCW ``polygons`` (m), whose edges the lidar sees as well.

        Why not a new StaticGeometry from the parts: a map world passes only its occupied/free
        boundary as ``segments``, which must stay as they are.
        """
        edges = [polygon_edges(p) for p in polygons]
        return StaticGeometry(self.circles, self.boxes, self.polygons + tuple(polygons),
                              np.concatenate([self.ray_segments, *edges]) if edges else self.ray_segments)

    def contains(self, points: FloatArray) -> BoolArray:
        """Which points (P, 2) lie inside (or on) any obstacle."""
        inside = np.zeros(len(points), dtype=bool)
        if len(self.circles):
            d2 = ((points[:, None, 0] - self.circles[None, :, 0]) ** 2
                  + (points[:, None, 1] - self.circles[None, :, 1]) ** 2)
            inside |= np.any(d2 <= self.circles[None, :, 2] ** 2, axis=1)
        if len(self.boxes):
            b = self.boxes
            inside |= np.any((points[:, None, 0] >= b[None, :, 0]) & (points[:, None, 0] <= b[None, :, 2])
                             & (points[:, None, 1] >= b[None, :, 1]) & (points[:, None, 1] <= b[None, :, 3]),
                             axis=1)
        for poly in self.polygons:
            inside |= points_in_convex(points, poly)
        return inside

    def boundary_distance(self, points: FloatArray) -> FloatArray:
        """Distance (P,) (m) from each point to the nearest obstacle boundary (inside or outside)."""
        dist = _segment_distance(points, np.concatenate(
            [polygon_edges(p) for p in self.polygons] + [box_edges(self.boxes)]))
        if len(self.circles):
            centre_d = np.hypot(points[:, None, 0] - self.circles[None, :, 0],
                                points[:, None, 1] - self.circles[None, :, 1])
            dist = np.minimum(dist, np.min(np.abs(centre_d - self.circles[None, :, 2]), axis=1))
        return dist

    def bounds(self) -> tuple[float, float, float, float]:
        """Bounding box (xmin, ymin, xmax, ymax) (m) of every obstacle."""
        c, b = self.circles, self.boxes
        xs: list[FloatArray] = [c[:, 0] - c[:, 2], c[:, 0] + c[:, 2], b[:, 0], b[:, 2]]
        ys: list[FloatArray] = [c[:, 1] - c[:, 2], c[:, 1] + c[:, 2], b[:, 1], b[:, 3]]
        xs += [p[:, 0] for p in self.polygons]
        ys += [p[:, 1] for p in self.polygons]
        x, y = np.concatenate(xs), np.concatenate(ys)
        if len(x) == 0:
            raise ValueError("world has no obstacles: bounds are undefined")
        return float(x.min()), float(y.min()), float(x.max()), float(y.max())
