"""A log-odds occupancy grid in the map frame that grows to fit whatever the scans reach.

Why log-odds: each scan adds evidence (hits raise, traversals lower a cell's log-odds), so a
person walking by or a grazing beam is outvoted by repeated observations, and clamping keeps
every cell able to change. Why growing: the SLAM map frame has no known extent; the grid starts
around the first scan and is re-allocated with a margin when a scan reaches past its edge. Cell
edges stay on multiples of the resolution in the map frame, so growing never shifts old cells.

Each scan updates a cell at most once (free cells and endpoint cells are deduplicated; an endpoint
wins over a traversal in the same scan), so cells near the sensor are not over-counted.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.raytrace import grid_coords
from nav_stack.core.geometry import FloatArray
from nav_stack.core.grid import GridSpec
from nav_stack.core.slam import integrate_jit

# Extra room (m) allocated beyond a scan's reach when the grid grows: re-allocations stay rare.
_GROW_MARGIN_M = 2.0


def _logit(p: float) -> float:
    return math.log(p / (1.0 - p))


class LogOddsGrid:
    """Occupancy evidence per cell; ``occupancy()`` renders the trinary OccupancyGrid values."""

    def __init__(
        self, resolution: float, hit_probability: float, miss_probability: float, clamp: tuple[float, float]
    ) -> None:
        self.resolution = resolution
        self._hit = np.float32(_logit(hit_probability))
        self._miss = np.float32(_logit(miss_probability))
        self._clamp = (np.float32(_logit(clamp[0])), np.float32(_logit(clamp[1])))
        self._cell0 = (0, 0)  # map-frame cell index (ix, iy) of array element [0, 0]
        self._log_odds = np.zeros((0, 0), dtype=np.float32)
        self._seen = np.zeros((0, 0), dtype=bool)
        self._stamp = np.zeros(0, dtype=np.int64)  # per-cell mark of the last scan that touched it
        self._next_id = 0  # id of the next scan integrated (integrate_jit's stamps)

    @property
    def spec(self) -> GridSpec | None:
        """Extent of the allocated grid (None before the first scan)."""
        if self._log_odds.size == 0:
            return None
        h, w = self._log_odds.shape
        return GridSpec(
            w, h, self.resolution, self._cell0[0] * self.resolution, self._cell0[1] * self.resolution
        )

    def state(self) -> tuple[tuple[int, int], npt.NDArray[np.float32], npt.NDArray[np.bool_]]:
        """(cell index of element [0, 0], log-odds, seen) as copies: what a saved graph stores so
        that a continued session starts from the very same map."""
        return self._cell0, self._log_odds.copy(), self._seen.copy()

    def load(
        self, cell0: tuple[int, int], log_odds: npt.NDArray[np.float32], seen: npt.NDArray[np.bool_]
    ) -> None:
        """Replace the evidence with a saved ``state()``."""
        if log_odds.shape != seen.shape:
            raise ValueError(f"LogOddsGrid.load: log_odds {log_odds.shape} and seen {seen.shape} differ")
        self._cell0 = (int(cell0[0]), int(cell0[1]))
        self._log_odds = np.array(log_odds, dtype=np.float32, copy=True)
        self._seen = np.array(seen, dtype=bool, copy=True)

    def _ensure_covers(self, xs: FloatArray, ys: FloatArray) -> GridSpec:
        """Grow the arrays so every point (m) lies on the grid; return the (new) spec."""
        res = self.resolution
        lo_x, hi_x = math.floor(float(xs.min()) / res), math.floor(float(xs.max()) / res)
        lo_y, hi_y = math.floor(float(ys.min()) / res), math.floor(float(ys.max()) / res)
        h, w = self._log_odds.shape
        x0, y0 = self._cell0
        if w and h and lo_x >= x0 and lo_y >= y0 and hi_x < x0 + w and hi_y < y0 + h:
            spec = self.spec
            assert spec is not None
            return spec
        margin = math.ceil(_GROW_MARGIN_M / res)
        if w and h:
            lo_x, lo_y = min(lo_x, x0), min(lo_y, y0)
            hi_x, hi_y = max(hi_x, x0 + w - 1), max(hi_y, y0 + h - 1)
        nx0, ny0 = lo_x - margin, lo_y - margin
        nw, nh = hi_x - lo_x + 1 + 2 * margin, hi_y - lo_y + 1 + 2 * margin
        log_odds = np.zeros((nh, nw), dtype=np.float32)
        seen = np.zeros((nh, nw), dtype=bool)
        if w and h:
            r, c = y0 - ny0, x0 - nx0
            log_odds[r : r + h, c : c + w] = self._log_odds
            seen[r : r + h, c : c + w] = self._seen
        self._log_odds, self._seen, self._cell0 = log_odds, seen, (nx0, ny0)
        spec = self.spec
        assert spec is not None
        return spec

    def integrate(self, origin: tuple[float, float], hits: FloatArray, misses: FloatArray) -> None:
        """Add one scan in the map frame: sensor ``origin``, (K, 2) ``hits`` and (J, 2) ``misses`` (m)."""
        self.integrate_all([(origin, hits, misses)])

    def integrate_all(self, scans: list[tuple[tuple[float, float], FloatArray, FloatArray]]) -> None:
        """Add scans (``integrate``'s arguments) in order, as one compiled pass (integrate_jit).

        Why one pass: a re-render after a loop closure integrates every node of the graph; grown
        once to cover them all, the grid is the same as after one ``integrate`` per scan.
        """
        if not scans:
            return
        every = np.vstack([np.vstack((hits, misses, np.array([origin]))) for origin, hits, misses in scans])
        spec = self._ensure_covers(every[:, 0], every[:, 1])
        if self._stamp.size != self._log_odds.size:
            self._stamp = np.full(self._log_odds.size, np.iinfo(np.int64).min, dtype=np.int64)
        sizes = np.array([[len(hits), len(misses)] for _, hits, misses in scans], dtype=np.int64)
        starts = np.concatenate(([0], np.cumsum(sizes.sum(axis=1)))).astype(np.int64)
        hit_starts = np.concatenate(([0], np.cumsum(sizes[:, 0]))).astype(np.int64)
        sensors = np.array([o for o, _, _ in scans], dtype=np.float64)
        origin = np.repeat(sensors, sizes.sum(axis=1), axis=0)  # each ray's sensor
        points = np.vstack([np.vstack((hits, misses)) for _, hits, misses in scans])
        keep_end = np.concatenate([np.arange(h + m) >= h for h, m in sizes])
        dx, dy = points[:, 0] - origin[:, 0], points[:, 1] - origin[:, 1]
        lengths, angles = np.hypot(dx, dy), np.arctan2(dy, dx)
        # raytrace.trace_cells' endpoints, rebuilt from length and angle as it does, bit for bit
        ex, ey = grid_coords(spec, origin[:, 0] + lengths * np.cos(angles),
                             origin[:, 1] + lengths * np.sin(angles))
        ox, oy = grid_coords(spec, sensors[:, 0], sensors[:, 1])
        hits = points[~keep_end]
        hx, hy = spec.world_to_cell(hits[:, 0], hits[:, 1])
        integrate_jit.integrate(self._log_odds, self._seen, self._stamp, np.column_stack((ox, oy)),
                                np.column_stack((ex, ey)), keep_end, (hy * spec.width + hx).astype(np.int64),
                                starts, hit_starts, self._next_id, (self._hit, self._miss, *self._clamp))
        self._next_id += len(scans)

    def occupied_points(
        self, center: tuple[float, float], half_size: float, occupied_thresh: float
    ) -> FloatArray:
        """Centres (m, map frame) of cells at or above ``occupied_thresh`` (probability) in the
        square of half side ``half_size`` (m) around ``center``: the map a new scan is matched to."""
        spec = self.spec
        if spec is None:
            return np.zeros((0, 2))
        res = self.resolution
        x0, y0 = self._cell0
        h, w = self._log_odds.shape
        c0 = max(0, math.floor((center[0] - half_size) / res) - x0)
        c1 = min(w, math.floor((center[0] + half_size) / res) - x0 + 1)
        r0 = max(0, math.floor((center[1] - half_size) / res) - y0)
        r1 = min(h, math.floor((center[1] + half_size) / res) - y0 + 1)
        if c0 >= c1 or r0 >= r1:
            return np.zeros((0, 2))
        rows, cols = np.nonzero(self._log_odds[r0:r1, c0:c1] >= _logit(occupied_thresh))
        return np.column_stack(((cols + c0 + x0 + 0.5) * res, (rows + r0 + y0 + 0.5) * res))

    def occupancy(self, occupied_thresh: float, free_thresh: float) -> tuple[npt.NDArray[np.int8], GridSpec]:
        """Trinary OccupancyGrid values (100 occupied, 0 free, -1 unknown) cropped to the observed cells."""
        spec = self.spec
        if spec is None or not self._seen.any():
            raise ValueError("the SLAM map is empty: no scan has been integrated yet")
        rows = np.flatnonzero(self._seen.any(axis=1))
        cols = np.flatnonzero(self._seen.any(axis=0))
        r0, r1, c0, c1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
        lo = self._log_odds[r0:r1, c0:c1]
        out = np.full(lo.shape, -1, dtype=np.int8)
        out[lo >= _logit(occupied_thresh)] = 100
        out[lo <= _logit(free_thresh)] = 0
        out[~self._seen[r0:r1, c0:c1]] = -1
        cropped = GridSpec(
            c1 - c0,
            r1 - r0,
            self.resolution,
            spec.origin_x + c0 * self.resolution,
            spec.origin_y + r0 * self.resolution,
        )
        return out, cropped
