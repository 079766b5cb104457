"""inflation_layer.inflate compiled with numba: distances, cost lookup and merge in one pass per row.

Why: the numpy reference builds a lethal mask, a distance array, a cost array and merged copies of
the whole update window; on a 2000 x 2000 global costmap those are several 4-million-cell
temporaries and 200 ms against Nav2's 50 ms. Here each row of the window goes from its column
distances (distance_jit) to merged costs while it is in cache, and the column distances are the only
region-sized array allocated. The rules are the reference's, in the same order; tests/unit/nav_stack/
test_costmap_jit.py checks identical costmaps on random maps, full and incremental updates.

Compiling takes a few seconds once per machine and loading the cached code well under a second, which
must not land in the first map's update: :class:`InflationLayer` calls :func:`warm_up` when it is
built (the costmap node's configure), as the planners call grid_search_jit.warm_up.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from nav_stack.core.costmap.distance_jit import WorkArray, column_distance, row_squared_distance, work_dtype
from nav_stack.core.costmap.layer import CostArray, Window
from nav_stack.core.grid import LETHAL_OBSTACLE, NO_INFORMATION


@njit(cache=True)
def _inflate(master: CostArray, x0: int, y0: int, x1: int, y1: int, rx0: int, ry0: int, table: CostArray,
             radius: int, threshold: int, g: WorkArray) -> None:
    """Inflate ``master[y0:y1, x0:x1]`` in place from the lethal cells of the region of ``master`` at
    (ry0, rx0) of ``g``'s shape; ``g`` takes the region's column distances."""
    column_distance(master, LETHAL_OBSTACLE, ry0, rx0, radius + 1, g)
    beyond = radius * radius + 1
    g2, best = np.empty(g.shape[1], dtype=g.dtype), np.empty(g.shape[1], dtype=g.dtype)
    for y in range(y0, y1):
        row_squared_distance(g[y - ry0], radius, g2, best)
        row = master[y]
        for x in range(x0, x1):
            cost = table[min(best[x - rx0], beyond)]
            old = row[x]
            if old == NO_INFORMATION:  # unknown takes only costs >= threshold
                if cost >= threshold:
                    row[x] = cost
            elif cost > old:  # known cells keep the larger cost
                row[x] = cost


def inflate(master: CostArray, window: Window, region: Window, table: CostArray, radius: int,
            threshold: int) -> None:
    """inflation_layer.inflate, compiled: the same arguments and result."""
    g = np.empty((region.y1 - region.y0, region.x1 - region.x0), dtype=work_dtype(radius))
    _inflate(master, window.x0, window.y0, window.x1, window.y1, region.x0, region.y0, table, radius,
             threshold, g)


def warm_up() -> None:
    """Compile (or load from the cache) the kernel now, on a 3 x 3 grid.

    Only its int16 variant (radii up to 127 cells: 6.35 m at 5 cm); a larger radius compiles the
    int32 variant in its first update, once per machine."""
    master = np.zeros((3, 3), dtype=np.uint8)
    master[1, 1] = LETHAL_OBSTACLE
    whole = Window(0, 0, 3, 3)
    inflate(master, whole, whole, np.zeros(3, dtype=np.uint8), 1, 1)
