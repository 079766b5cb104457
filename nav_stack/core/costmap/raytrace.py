"""Vectorised ray tracing over a grid: the cells every beam passes through, all beams at once.

Why: the obstacle layer clears the free space between the sensor and each return. Looping over
360 beams × 60 cells in Python would cost more than the rest of the update, so each ray is
sampled at most one cell apart in one (beams × steps) array (a DDA), keeping the 8-connected line
of cells Bresenham would visit.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from nav_stack.core.costmap.layer import CostArray, Window
from nav_stack.core.grid import FloatArray, GridSpec, IntArray

#: (grid, its spec, sensor origin (m), ray lengths (m), ray angles (rad), min length (m), cost to set)
#: -> the window of the cells it changed: :func:`clear_rays` or raytrace_jit.clear_rays
ClearRays = Callable[[CostArray, GridSpec, tuple[float, float], FloatArray, FloatArray, float, int], Window]


def grid_coords(spec: GridSpec, x: FloatArray, y: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Continuous grid coordinates (cells; cell i spans [i, i+1)) of frame points (m)."""
    dx = np.asarray(x, dtype=np.float64) - spec.origin_x
    dy = np.asarray(y, dtype=np.float64) - spec.origin_y
    if spec.origin_yaw != 0.0:
        c, s = math.cos(spec.origin_yaw), math.sin(spec.origin_yaw)
        dx, dy = c * dx + s * dy, -s * dx + c * dy
    return dx / spec.resolution, dy / spec.resolution


def trace_cells(
    spec: GridSpec,
    origin: tuple[float, float],
    lengths: FloatArray,
    angles: FloatArray,
    min_length: float = 0.0,
    include_end: bool = False,
) -> tuple[IntArray, IntArray]:
    """Cells ``(mx, my)`` (in the grid, possibly repeated) along rays from ``origin`` (m).

    Ray i has direction ``angles[i]`` (rad, frame) and length ``lengths[i]`` (m). Cells nearer than
    ``min_length`` are skipped; the ray's end cell is left out unless ``include_end``.
    """
    if lengths.size == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty
    ox, oy = grid_coords(spec, np.array(origin[0]), np.array(origin[1]))
    ex, ey = grid_coords(spec, origin[0] + lengths * np.cos(angles), origin[1] + lengths * np.sin(angles))
    steps = np.ceil(np.maximum(np.abs(ex - ox), np.abs(ey - oy)) * 2.0).astype(np.int64) + 1
    k = np.arange(int(steps.max()) + 1, dtype=np.float64)
    t = np.minimum(k[None, :] / steps[:, None], 1.0)
    px = np.floor(ox + (ex - ox)[:, None] * t).astype(np.int64)
    py = np.floor(oy + (ey - oy)[:, None] * t).astype(np.int64)
    keep = t * lengths[:, None] >= min_length
    if not include_end:
        end_x, end_y = np.floor(ex).astype(np.int64)[:, None], np.floor(ey).astype(np.int64)[:, None]
        keep &= (px != end_x) | (py != end_y)
    keep &= spec.in_bounds(px, py)
    return px[keep], py[keep]


def clear_rays(grid: CostArray, spec: GridSpec, origin: tuple[float, float], lengths: FloatArray,
               angles: FloatArray, min_length: float, value: int) -> Window:
    """Set the cells :func:`trace_cells` gives (end cells left out) to ``value`` in ``grid``; the
    smallest window holding the cells whose value changed (empty when none did).

    Why only the changed cells: a robot standing among known free space clears the same cells scan
    after scan; reporting them would redraw, reinflate and republish a 6 m square each update for
    nothing. The master grid is a function of the layers' cells, so unchanged cells need no redraw.
    The numpy reference of raytrace_jit.clear_rays."""
    mx, my = trace_cells(spec, origin, lengths, angles, min_length)
    changed = grid[my, mx] != value
    grid[my, mx] = value
    return Window.around(mx[changed], my[changed])
