"""The bounded distance transform of distance.py compiled with numba: the same squared distances.

Why: inflating a 2000 x 2000 global costmap spent about 95 % of its 200 ms in distance.py's numpy
passes, which stream several 16 MB temporaries through memory once per shift (2R shifts). Compiled,
the passes run one row at a time in cache and the shifted minimums become SIMD loops: about 7 ms of
CPU for the whole map. numba for the reasons grid_search_jit.py gives (no build step, the same
Python next to its reference), with the same idiom: ``@njit(cache=True)``, so the machine code is
compiled once per machine and loaded from ``__pycache__`` afterwards.

Same algorithm, same values: column distances capped at R + 1, then d²(x) = min over |k| ≤ R of
g(x + k)² + k² along each row (the caller maps values above R² to "beyond"). The passes are the
pieces of inflation_jit's kernel, whose test (tests/unit/nav_stack/test_costmap_jit.py) compares
whole costmaps with the reference's. The work arrays are int16 while every sum fits (R ≤ 127 cells,
:func:`work_dtype`): twice the cells per SIMD instruction of int32. The grid is uint8 with a
``mark`` value, so lethal cells are read straight from the master costmap.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from numba import njit

#: int16 or int32 (:func:`work_dtype`), in every array the compiled passes write.
WorkArray = npt.NDArray[np.int16 | np.int32]


def work_dtype(max_cells: int) -> type[np.int16] | type[np.int32]:
    """int16 when every g² + k² (g ≤ max_cells + 1, k ≤ max_cells) fits in it, else int32."""
    return np.int16 if 2 * (max_cells + 1) ** 2 <= np.iinfo(np.int16).max else np.int32


@njit(cache=True)
def column_distance(grid: npt.NDArray[np.uint8], mark: int, y0: int, x0: int, cap: int,
                    dist: WorkArray) -> None:
    """``dist`` = cells along axis 0 from each cell of the window of ``grid`` at (y0, x0) (the shape
    of ``dist``) to the nearest ``mark`` cell of its column in the window, capped at ``cap``:
    counted downwards from the last mark above, then lowered by the count upwards from below."""
    height, width = dist.shape
    for x in range(width):
        dist[0, x] = 0 if grid[y0, x0 + x] == mark else cap
    for y in range(1, height):
        for x in range(width):
            dist[y, x] = 0 if grid[y0 + y, x0 + x] == mark else min(dist[y - 1, x] + 1, cap)
    for y in range(height - 2, -1, -1):
        for x in range(width):
            dist[y, x] = min(dist[y, x], dist[y + 1, x] + 1)


@njit(cache=True)
def _min_plus(best: WorkArray, g2: WorkArray, k2: np.int16 | np.int32) -> None:
    """best = min(best, g2 + k2) elementwise in the arrays' own type (``type(k2)``): kept that
    narrow, LLVM packs the loop into SIMD instructions."""
    for i in range(best.shape[0]):
        best[i] = min(best[i], type(k2)(g2[i] + k2))


@njit(cache=True)
def row_squared_distance(g: WorkArray, max_cells: int, g2: WorkArray, best: WorkArray) -> None:
    """``best`` = min over |k| ≤ ``max_cells`` of g(x + k)² + k² for one row (``g2`` is scratch)."""
    width = g.shape[0]
    for x in range(width):
        g2[x] = g[x] * g[x]
        best[x] = g2[x]
    for k in range(1, min(max_cells, width - 1) + 1):
        k2 = type(g2[0])(k * k)
        _min_plus(best[k:], g2[: width - k], k2)
        _min_plus(best[: width - k], g2[k:], k2)
