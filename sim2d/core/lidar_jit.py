"""The lidar's ray caster compiled with numba: beams walk a uniform bin grid and stop at the first hit.

Why: lidar.cast_rays intersects every beam with every segment and circle in range, (beams x items)
arrays at once. On a generated warehouse (thousands of shelf and wall edges within a TB4's 12 m) a scan
was 41 % of the simulator's CPU (issue 44). Here the world's segments and circles are sorted once into
square bins (:class:`BinnedGeometry`); each beam visits the bins it crosses in order (Amanatides-Woo
traversal) and stops as soon as its nearest hit lies before the end of the current bin, so a beam pays
for the few items near its path, not for the whole world.

The intersection tests are cast_rays' own, in the same float64 arithmetic and with the beams'
directions computed by numpy as there, so both casters return the same ranges
(tests/unit/sim2d/test_lidar_jit.py checks them on random worlds and poses). cast_rays stays the
reference: short, vectorised, easy to read.

Why the early stop is exact: an item is filed under every bin its bounding box (padded by :data:`PAD`)
touches, so the hit point's bin holds it; a hit found so far at distance t <= the current bin's exit
cannot be beaten by an item met only in a later bin, whose points all lie beyond that exit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from numba import njit

from sim2d.core.geometry import FloatArray, StaticGeometry

IntArray = npt.NDArray[np.int64]
PAD = 1e-6  # m added around each item's bounding box when filing it, against rounding at bin edges
MIN_BIN = 0.5  # m: the bin side on small worlds; larger worlds keep their bin count near MAX_BINS
MAX_BINS = 250_000


@njit(cache=True)
def _file_items(boxes: FloatArray, x0: float, y0: float, size: float, nx: int, ny: int
                ) -> tuple[IntArray, IntArray]:
    """CSR lists of the items whose (padded) boxes ``[xmin, ymin, xmax, ymax]`` touch each bin: the
    items of bin b are ``items[start[b]:start[b + 1]]``, bins numbered ``iy * nx + ix``."""
    count = np.zeros(nx * ny + 1, dtype=np.int64)
    span = np.empty((len(boxes), 4), dtype=np.int64)
    for k in range(len(boxes)):
        ix0 = max(0, min(nx - 1, math.floor((boxes[k, 0] - x0) / size)))
        iy0 = max(0, min(ny - 1, math.floor((boxes[k, 1] - y0) / size)))
        ix1 = max(0, min(nx - 1, math.floor((boxes[k, 2] - x0) / size)))
        iy1 = max(0, min(ny - 1, math.floor((boxes[k, 3] - y0) / size)))
        span[k, 0], span[k, 1], span[k, 2], span[k, 3] = ix0, iy0, ix1, iy1
        for iy in range(iy0, iy1 + 1):
            for ix in range(ix0, ix1 + 1):
                count[iy * nx + ix + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    items = np.empty(start[-1], dtype=np.int64)
    for k in range(len(boxes)):
        for iy in range(span[k, 1], span[k, 3] + 1):
            for ix in range(span[k, 0], span[k, 2] + 1):
                b = iy * nx + ix
                items[fill[b]] = k
                fill[b] += 1
    return start, items


@dataclass(frozen=True)
class BinnedGeometry:
    """A StaticGeometry's segments and circles filed into ``nx`` x ``ny`` square bins of ``size`` m
    from ``(x0, y0)`` (m); ``*_start`` / ``*_items`` are the CSR lists of :func:`_file_items`."""

    segments: FloatArray
    circles: FloatArray
    x0: float
    y0: float
    size: float
    nx: int
    ny: int
    seg_start: IntArray
    seg_items: IntArray
    circle_start: IntArray
    circle_items: IntArray

    @classmethod
    def of(cls, geometry: StaticGeometry) -> BinnedGeometry:
        segments = np.ascontiguousarray(geometry.ray_segments, dtype=np.float64).reshape(-1, 4)
        circles = np.ascontiguousarray(geometry.circles, dtype=np.float64).reshape(-1, 3)
        seg_boxes = np.column_stack([np.minimum(segments[:, 0], segments[:, 2]),
                                     np.minimum(segments[:, 1], segments[:, 3]),
                                     np.maximum(segments[:, 0], segments[:, 2]),
                                     np.maximum(segments[:, 1], segments[:, 3])])
        circle_boxes = np.column_stack([circles[:, 0] - circles[:, 2], circles[:, 1] - circles[:, 2],
                                        circles[:, 0] + circles[:, 2], circles[:, 1] + circles[:, 2]])
        seg_boxes = seg_boxes + np.array([-PAD, -PAD, PAD, PAD])
        circle_boxes = circle_boxes + np.array([-PAD, -PAD, PAD, PAD])
        every = np.concatenate([seg_boxes, circle_boxes])
        if not len(every):
            every = np.zeros((1, 4))
        x0, y0 = float(every[:, 0].min()), float(every[:, 1].min())
        width = max(float(every[:, 2].max()) - x0, MIN_BIN)
        height = max(float(every[:, 3].max()) - y0, MIN_BIN)
        size = max(MIN_BIN, math.sqrt(width * height / MAX_BINS))
        nx, ny = math.ceil(width / size) + 1, math.ceil(height / size) + 1
        seg_start, seg_items = _file_items(seg_boxes, x0, y0, size, nx, ny)
        circle_start, circle_items = _file_items(circle_boxes, x0, y0, size, nx, ny)
        return cls(segments, circles, x0, y0, size, nx, ny, seg_start, seg_items, circle_start, circle_items)


@njit(cache=True)
def _segment_hit(seg: FloatArray, j: int, ox: float, oy: float, dx: float, dy: float) -> float:
    """Distance along the beam to segment ``j`` (cast_rays' test: front faces only), or +inf."""
    px, py = seg[j, 0] - ox, seg[j, 1] - oy
    ex, ey = seg[j, 2] - seg[j, 0], seg[j, 3] - seg[j, 1]
    numerator = py * ex - px * ey
    if not numerator > 0.0:
        return math.inf
    denom = dy * ex - dx * ey
    u_num = py * dx - px * dy
    if denom > 0.0 and u_num >= 0.0 and u_num <= denom:
        return float(numerator / denom)
    return math.inf


@njit(cache=True)
def _circle_hit(circles: FloatArray, j: int, ox: float, oy: float, dx: float, dy: float) -> float:
    """Distance along the beam to circle ``j`` (its exit point from inside), or +inf."""
    cx, cy, radius = circles[j, 0] - ox, circles[j, 1] - oy, circles[j, 2]
    b = dx * cx + dy * cy
    disc = b * b - (cx * cx + cy * cy - radius * radius)
    root = math.sqrt(max(disc, 0.0))
    if not (disc >= 0.0 and b + root >= 0.0):
        return math.inf
    return float(b - root if b >= root else b + root)


@njit(cache=True)
def _cast(ox: float, oy: float, cos_a: FloatArray, sin_a: FloatArray, max_range: float,
          seg: FloatArray, circles: FloatArray, x0: float, y0: float, size: float, nx: int, ny: int,
          seg_start: IntArray, seg_items: IntArray, circle_start: IntArray, circle_items: IntArray,
          out: FloatArray) -> None:
    """``out[i]``: distance to the first hit of beam i from (ox, oy), +inf beyond ``max_range``."""
    x1, y1 = x0 + nx * size, y0 + ny * size
    for i in range(len(cos_a)):
        dx, dy = cos_a[i], sin_a[i]
        out[i] = math.inf
        t_in, t_out = 0.0, max_range  # the part of the beam inside the bin grid (slab clipping)
        for o, d, lo, hi in ((ox, dx, x0, x1), (oy, dy, y0, y1)):
            if d == 0.0:
                if o < lo or o > hi:
                    t_in = math.inf
            else:
                ta, tb = (lo - o) / d, (hi - o) / d
                t_in, t_out = max(t_in, min(ta, tb)), min(t_out, max(ta, tb))
        if t_in > t_out:
            continue
        ix = max(0, min(nx - 1, math.floor((ox + dx * t_in - x0) / size)))
        iy = max(0, min(ny - 1, math.floor((oy + dy * t_in - y0) / size)))
        step_x, step_y = (1 if dx > 0.0 else -1), (1 if dy > 0.0 else -1)
        next_x = ((x0 + (ix + (1 if dx > 0.0 else 0)) * size - ox) / dx) if dx != 0.0 else math.inf
        next_y = ((y0 + (iy + (1 if dy > 0.0 else 0)) * size - oy) / dy) if dy != 0.0 else math.inf
        delta_x = size / abs(dx) if dx != 0.0 else math.inf
        delta_y = size / abs(dy) if dy != 0.0 else math.inf
        best = math.inf
        while True:
            b = iy * nx + ix
            for k in range(seg_start[b], seg_start[b + 1]):
                best = min(best, _segment_hit(seg, seg_items[k], ox, oy, dx, dy))
            for k in range(circle_start[b], circle_start[b + 1]):
                best = min(best, _circle_hit(circles, circle_items[k], ox, oy, dx, dy))
            leave = min(next_x, next_y)
            if best <= leave or leave > t_out:
                break
            if next_x < next_y:
                ix, next_x = ix + step_x, next_x + delta_x
            else:
                iy, next_y = iy + step_y, next_y + delta_y
            if ix < 0 or ix >= nx or iy < 0 or iy >= ny:
                break
        if best <= max_range:
            out[i] = best


@njit(cache=True)
def _cast_each(ox: float, oy: float, cos_a: FloatArray, sin_a: FloatArray, max_range: float,
               seg: FloatArray, circles: FloatArray, out: FloatArray) -> None:
    """``out[i]``: distance to beam i's first hit, testing every item (no bins); +inf beyond ``max_range``."""
    for i in range(len(cos_a)):
        best = math.inf
        for j in range(len(seg)):
            best = min(best, _segment_hit(seg, j, ox, oy, cos_a[i], sin_a[i]))
        for j in range(len(circles)):
            best = min(best, _circle_hit(circles, j, ox, oy, cos_a[i], sin_a[i]))
        out[i] = best if best <= max_range else math.inf


def cast_each(origin: tuple[float, float], angles: FloatArray, geometry: StaticGeometry,
              max_range: float) -> FloatArray:
    """cast_rays' signature and result for a handful of items, each beam testing every item.

    Why: a fleet's other robots (sim2d.core.fleet) are a few shapes that move every step; filing them
    into bins per scan would cost more than testing them all, and cast_rays' numpy arrays cost more
    in call overhead than the arithmetic (about 100 µs against a few for 4 robots, measured while
    writing bench/bench_fleet.py).
    """
    segments = np.ascontiguousarray(geometry.ray_segments, dtype=np.float64).reshape(-1, 4)
    circles = np.ascontiguousarray(geometry.circles, dtype=np.float64).reshape(-1, 3)
    out = np.empty(len(angles))
    _cast_each(float(origin[0]), float(origin[1]), np.cos(angles), np.sin(angles), float(max_range),
               segments, circles, out)
    return out


class BinnedCaster:
    """cast_rays' signature and result, compiled; keeps the bins of the geometry it last saw.

    The simulator replaces its lidar's geometry when a circle is added at run time; a geometry other
    than the last one (by identity: StaticGeometry is frozen) is filed anew.
    """

    def __init__(self) -> None:
        self._geometry: StaticGeometry | None = None
        self._bins: BinnedGeometry | None = None

    def bins(self, geometry: StaticGeometry) -> BinnedGeometry:
        if self._bins is None or geometry is not self._geometry:
            self._geometry, self._bins = geometry, BinnedGeometry.of(geometry)
        return self._bins

    def __call__(self, origin: tuple[float, float], angles: FloatArray, geometry: StaticGeometry,
                 max_range: float) -> FloatArray:
        """Distance (B,) (m) along each ray from ``origin`` to the first obstacle; +inf beyond ``max_range``
        (m) or for no hit."""
        g = self.bins(geometry)
        out = np.empty(len(angles))
        _cast(float(origin[0]), float(origin[1]), np.cos(angles), np.sin(angles), float(max_range),
              g.segments, g.circles, g.x0, g.y0, g.size, g.nx, g.ny, g.seg_start, g.seg_items,
              g.circle_start, g.circle_items, out)
        return out


def warm_up() -> None:
    """Compile (or load from the cache) the kernels now, on one box and one circle."""
    geometry = StaticGeometry(circles=np.array([[2.0, 0.0, 0.5]]), boxes=np.array([[-3.0, -1.0, -2.0, 1.0]]))
    angles = np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False)
    BinnedCaster()((0.0, 0.0), angles, geometry, 5.0)
    cast_each((0.0, 0.0), angles, geometry, 5.0)
