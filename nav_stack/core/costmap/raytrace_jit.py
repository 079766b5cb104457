"""The obstacle layer's ray clearing compiled with numba: walk each beam and free its cells in place.

Why: raytrace.trace_cells builds (beams x steps) float and index arrays for a whole scan, about
360 x 120 cells for a 3 m clearing range at 5 cm, several temporaries each, before one fancy-index
write. Clearing a scan that way was a fifth of the nav2 process's CPU with the robot standing still
(py-spy, idle stack at ``--rtf max``, 2026-11-28), and two costmaps clear every scan. Here each beam is
walked cell by cell into the grid, and the window of the cells it changed is kept as four integers.

The rules are trace_cells', in the same float64 arithmetic, so the grid and the window are identical
(tests/unit/nav_stack/test_costmap_jit.py checks it on random rays): a ray from the sensor to its end
point (grid coordinates, cells) is sampled at ``ceil(2 * max(|dx|, |dy|)) + 1`` steps, a sample is
kept when it lies ``min_length`` (m) or more from the sensor, the end point's own cell is left out,
and cells off the grid are skipped. The SLAM map update (slam/integrate_jit.py) walks its rays with the
same two helpers.

Compiling takes a few seconds once per machine (scripts/compile_kernels.py does it at setup); the
obstacle layer calls :func:`warm_up` when it is built, so loading the cached code never lands in a
scan's update.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from numba import njit

from nav_stack.core.costmap.layer import CostArray, Window
from nav_stack.core.costmap.raytrace import grid_coords
from nav_stack.core.grid import FloatArray, GridSpec


@njit(cache=True, inline="always")
def ray_steps(dx: float, dy: float) -> int:
    """Samples (minus one) along a ray of ``(dx, dy)`` cells: at most half a cell apart."""
    return math.ceil(max(abs(dx), abs(dy)) * 2.0) + 1


@njit(cache=True, inline="always")
def ray_sample(ox: float, oy: float, dx: float, dy: float, k: int, steps: int) -> tuple[float, int, int]:
    """Sample ``k`` of ``steps`` along the ray from ``(ox, oy)``: its fraction t and its cell."""
    t = min(k / steps, 1.0)
    return t, math.floor(ox + dx * t), math.floor(oy + dy * t)


@njit(cache=True)
def _clear(grid: CostArray, ox: float, oy: float, ex: FloatArray, ey: FloatArray, lengths: FloatArray,
           min_length: float, value: int, box: npt.NDArray[np.int64]) -> None:
    """Set the cells of every ray (see the module doc) to ``value``; widen ``box`` (x0, y0, x1, y1,
    end-exclusive) to hold each cell whose value this changed. The box lives in locals while the rays
    are walked (in the array, its four writes per cell halved the kernel's speed)."""
    height, width = grid.shape
    bx0, by0, bx1, by1 = box[0], box[1], box[2], box[3]
    for i in range(len(ex)):
        dx, dy = ex[i] - ox, ey[i] - oy
        steps = ray_steps(dx, dy)
        end_x, end_y = math.floor(ex[i]), math.floor(ey[i])
        length = lengths[i]
        for k in range(steps + 1):
            t, px, py = ray_sample(ox, oy, dx, dy, k, steps)
            if t * length < min_length or (px == end_x and py == end_y):
                continue
            if px < 0 or px >= width or py < 0 or py >= height or grid[py, px] == value:
                continue
            grid[py, px] = value
            bx0, by0 = min(bx0, px), min(by0, py)
            bx1, by1 = max(bx1, px + 1), max(by1, py + 1)
    box[0], box[1], box[2], box[3] = bx0, by0, bx1, by1


def clear_rays(grid: CostArray, spec: GridSpec, origin: tuple[float, float], lengths: FloatArray,
               angles: FloatArray, min_length: float, value: int) -> Window:
    """Set to ``value`` the cells of ``grid`` (of ``spec``) that trace_cells gives for these rays
    (``lengths`` m, ``angles`` rad in the grid's frame, from ``origin`` m); the smallest window
    holding the cells whose value changed (empty when none did)."""
    ox, oy = grid_coords(spec, np.array(origin[0]), np.array(origin[1]))
    ex, ey = grid_coords(spec, origin[0] + lengths * np.cos(angles), origin[1] + lengths * np.sin(angles))
    box = np.array([spec.width, spec.height, 0, 0], dtype=np.int64)  # empty until a cell changes
    _clear(grid, float(ox), float(oy), ex, ey, np.asarray(lengths, dtype=np.float64), float(min_length),
           value, box)
    window = Window(*(int(v) for v in box))
    return window if not window.is_empty else Window.empty()


def warm_up() -> None:
    """Compile (or load from the cache) the kernel now, on one ray across a 3 x 3 grid."""
    spec = GridSpec(3, 3, 1.0)
    clear_rays(np.zeros((3, 3), dtype=np.uint8), spec, (0.5, 0.5), np.array([2.0]), np.array([0.7]), 0.0, 0)
