"""nav2_smoother's SimpleSmoother (Jazzy): pull a path toward straightness while it stays near itself.

Each iteration moves every interior point ``y_i`` of a segment by
``w_data·(x_i − y_i) + w_smooth·(y_{i+1} + y_{i−1} − 2·y_i)``, where ``x_i`` is the point as it came in
and ``y_{i−1}`` has already moved this iteration (a Gauss-Seidel sweep, in path order, as Nav2's loop
runs); the segment's end points never move. Iterations stop once the summed movement of a sweep falls
below ``tolerance``, or after ``max_its``. A sweep that would put a point on a cell above
MAX_NON_OBSTACLE (inscribed or lethal; unknown is allowed) is thrown away and the segment keeps the
sweep before it. With ``do_refinement`` the converged segment is smoothed again ``refinement_num``
times, each time anchored to the previous result. Headings are then recomputed along the new positions.

Segments: the path is cut at cusps (the direction of travel turns by more than 90°) and at turns on
the spot, so a reversing manoeuvre keeps its cusp; only segments spanning at least
SEGMENT_MIN_STEPS steps are smoothed (Jazzy's rule), shorter ones are left as they are.

Time: ``max_time`` (s, on the injected ``clock``) bounds the whole call; once it is spent the call
ends with ``timed_out`` and the path smoothed so far (Nav2 throws SmootherTimedOut, the server answers
TIMEOUT). Nav2 restarts the budget for each refinement pass; here one deadline covers them all.

Why a convolution: one sweep is the first-order recurrence ``y_new[i] = b[i] + w_smooth·y_new[i−1]``
with ``b`` built from the previous sweep, whose solution is ``b`` convolved with ``w_smooth^k``. The
powers fall below 1e-18 within a few dozen terms, so the truncated convolution gives Nav2's sequential
result to rounding, in one numpy call per sweep instead of a Python loop over the points.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import CostGrid
from nav_stack.core.geometry import FloatArray, angle_diff, normalize_angles
from nav_stack.core.grid import MAX_NON_OBSTACLE, NO_INFORMATION

#: a segment is smoothed when its last index is at least this far past its first (Jazzy: end − start > 9)
SEGMENT_MIN_STEPS = 10
#: m (and rad): closer points count as one position; a heading change there is a turn on the spot
SAME_POSITION = 1e-4
#: relative size of the dropped tail of the sweep's convolution kernel (below float64 rounding)
KERNEL_CUTOFF = 1e-18


@dataclass(frozen=True)
class SimpleSmootherParams:
    """``<smoother id>.*`` parameters of nav2_smoother::SimpleSmoother (Jazzy defaults)."""

    tolerance: float = 1e-10  # summed movement (m) of a sweep below which smoothing has converged
    max_its: int = 1000  # iterations before giving up on convergence (the last sweep is kept)
    w_data: float = 0.2  # pull toward the original point
    w_smooth: float = 0.3  # pull toward the neighbours' midpoint
    do_refinement: bool = True  # smooth the converged result again
    refinement_num: int = 2  # how many times (>= 1)
    # Kilted's knob (Jazzy always cuts the path at cusps, which the default keeps): false smooths the
    # path as one segment, across cusps.
    enforce_path_inversion: bool = True

    def __post_init__(self) -> None:
        if not (self.tolerance >= 0.0 and self.max_its >= 1 and self.refinement_num >= 1):
            raise ValueError(f"need tolerance >= 0, max_its >= 1 and refinement_num >= 1, got {self}")
        if not (self.w_data >= 0.0 and 0.0 <= self.w_smooth < 1.0):
            raise ValueError("need w_data >= 0 and 0 <= w_smooth < 1 (from w_smooth 1 on a sweep "
                             f"amplifies every change along the path), got w_data {self.w_data}, "
                             f"w_smooth {self.w_smooth}")


@dataclass(frozen=True)
class SmoothingOutcome:
    """The smoothed (N, 3) path; ``timed_out`` when the time ran out (or ``should_stop`` said so)."""

    path: FloatArray
    timed_out: bool = False


class _OutOfTime(Exception):  # noqa: N818 - internal signal, like nav2_core::SmootherTimedOut
    """The deadline passed (or the caller asked to stop) during a sweep loop."""


def directional_segments(path: FloatArray) -> list[tuple[int, int]]:
    """``(start, end)`` index pairs (inclusive, consecutive segments share their joint) of the stretches
    between cusps and turns on the spot of an (N, 3) path; one segment when there are none."""
    n = len(path)
    if n < 3:
        return [(0, max(n - 1, 0))]
    before = path[1:-1, :2] - path[:-2, :2]
    after = path[2:, :2] - path[1:-1, :2]
    cusp = np.einsum("ij,ij->i", before, after) < 0.0
    turn = np.abs(normalize_angles(path[2:, 2] - path[1:-1, 2]))
    on_spot = (np.abs(after) < SAME_POSITION).all(axis=1) & (turn > SAME_POSITION)
    cuts = (np.nonzero(cusp | on_spot)[0] + 1).tolist()
    bounds = [0, *cuts, n - 1]
    return list(itertools.pairwise(bounds))


def update_orientations(segment: FloatArray) -> None:
    """Set each pose's yaw (in place) to face the next pose, flipped by π on a reversing segment; the last
    pose, and poses on the same spot as the next, keep theirs. Reversing: the heading of pose 1 points
    more than 90° away from the direction 1 → 2 (Nav2's test). Needs at least 3 poses."""
    step = segment[2, :2] - segment[1, :2]
    reversing = abs(angle_diff(math.atan2(step[1], step[0]), float(segment[1, 2]))) > math.pi / 2
    d = np.diff(segment[:, :2], axis=0)
    moving = ~(np.abs(d) < SAME_POSITION).all(axis=1)
    heading = np.arctan2(d[:, 1], d[:, 0]) + (math.pi if reversing else 0.0)
    segment[:-1, 2] = np.where(moving, normalize_angles(heading), segment[:-1, 2])


class SimpleSmoother:
    """Smooths (N, 3) paths; ``grid`` (the costmap, same frame) vetoes sweeps that touch obstacles."""

    def __init__(self, params: SimpleSmootherParams | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.params = params or SimpleSmootherParams()
        self._clock = clock
        self.iterations = 0  # sweeps run by the last call, all passes (for tests and benchmarks)

    def smooth(self, path: FloatArray, max_time: float, grid: CostGrid | None = None,
               should_stop: Callable[[], bool] = lambda: False) -> SmoothingOutcome:
        """The smoothed copy of ``path`` (N, 3), within ``max_time`` s of the clock."""
        out = np.array(path, dtype=np.float64)
        self.iterations = 0
        deadline = self._clock() + max_time
        p = self.params
        segments = directional_segments(out) if p.enforce_path_inversion else [(0, len(out) - 1)]
        for start, end in segments:
            if end - start < SEGMENT_MIN_STEPS:
                continue
            try:
                out[start:end + 1] = self._smooth_segment(out[start:end + 1], grid, deadline, should_stop)
            except _OutOfTime as stopped:
                out[start:end + 1] = stopped.args[0]
                return SmoothingOutcome(out, timed_out=True)
        return SmoothingOutcome(out)

    def _smooth_segment(self, segment: FloatArray, grid: CostGrid | None, deadline: float,
                        should_stop: Callable[[], bool]) -> FloatArray:
        """The first pass, then the refinement passes on its result (each anchored to the last)."""
        p = self.params
        passes = 1 + (p.refinement_num if p.do_refinement else 0)
        current: FloatArray = segment.copy()
        for _ in range(passes):
            current, converged = self._pass(current, grid, deadline, should_stop)
            if not converged:  # max_its or a collision: Nav2 skips the refinement too
                break
        update_orientations(current)
        return current

    def _pass(self, anchor: FloatArray, grid: CostGrid | None, deadline: float,
              should_stop: Callable[[], bool]) -> tuple[FloatArray, bool]:
        """Sweep until converged (True) or stopped by max_its or a collision (False)."""
        p = self.params
        kernel = _sweep_kernel(p.w_smooth, len(anchor))
        data = anchor[:, :2]
        last = anchor.copy()
        its = 0
        while True:
            its += 1
            if its >= p.max_its:
                return last, False
            if self._clock() > deadline or should_stop():
                update_orientations(last)
                raise _OutOfTime(last)
            self.iterations += 1
            moved = last.copy()
            moved[:-1, :2] = _sweep(data, last[:, :2], p.w_data, p.w_smooth, kernel)
            if grid is not None and _touches_obstacle(grid, moved[1:-1]):
                return last, False
            change = float(np.abs(moved[1:-1, :2] - last[1:-1, :2]).sum())
            last = moved
            if change < p.tolerance:
                return last, True


def _sweep_kernel(w_smooth: float, n: int) -> FloatArray:
    """``w_smooth^k`` for k = 0, 1, ... until the terms are negligible (at most ``n`` of them)."""
    if w_smooth <= 0.0:
        return np.ones(1)
    length = min(n, max(1, math.ceil(math.log(KERNEL_CUTOFF) / math.log(w_smooth))))
    return np.asarray(w_smooth ** np.arange(length), dtype=np.float64)


def _sweep(data: FloatArray, y: FloatArray, w_data: float, w_smooth: float, kernel: FloatArray) -> FloatArray:
    """Points 0 .. N−2 after one Gauss-Seidel sweep (point 0 unchanged, point N−1 fixed as well)."""
    b = np.empty((len(y) - 1, 2))
    b[0] = y[0]
    b[1:] = (1.0 - w_data - 2.0 * w_smooth) * y[1:-1] + w_data * data[1:-1] + w_smooth * y[2:]
    m = len(b)
    out = np.column_stack([np.convolve(b[:, 0], kernel)[:m], np.convolve(b[:, 1], kernel)[:m]])
    return np.asarray(out, dtype=np.float64)


def _touches_obstacle(grid: CostGrid, points: FloatArray) -> bool:
    """Whether a point lies on an inscribed or lethal cell (unknown and off-grid cells are allowed)."""
    cost = grid.cost_at(points[:, 0], points[:, 1])
    return bool(((cost > MAX_NON_OBSTACLE) & (cost != NO_INFORMATION)).any())
