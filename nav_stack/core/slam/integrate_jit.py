"""The log-odds scan update compiled with numba: trace, deduplicate and update in one pass per scan.

Why: after a loop closure the SLAM map is re-rendered from every optimised pose. In numpy each scan
costs about 0.7 ms (a (beams x steps) coordinate array, two deduplications through a scratch array),
so a 700-node graph in turtlebot3_house took 0.5 s and a house-sized exploration several seconds on a
loaded 2-core machine, on the executor thread: the lifecycle manager declared the slam node dead
(no bond heartbeat for 4 s) and reset it, losing the map. Here a scan costs about 0.2 ms with its
numpy preparation, a whole graph goes in one call, and rerender.py spreads a re-render over scans.

The rules are raytrace.trace_cells' (each ray walked by raytrace_jit's helpers) and LogOddsGrid's, in
the same float64 / float32 arithmetic, so the grid is bit-identical (tests/unit/nav_stack/
test_slam_map_update.py checks it): a ray from the sensor origin to each endpoint is sampled at
``ceil(2 * max(|dx|, |dy|)) + 1`` steps (cells), cells off the grid are skipped, a hit ray leaves out
its end cell and a miss ray keeps it; per scan every cell changes at most once and an endpoint wins
over a traversal.

Compiling takes seconds once per machine (scripts/compile_kernels.py does it at setup); the mapper
calls :func:`warm_up` when it is built, so loading the cached code never lands in a scan callback.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from numba import njit

from nav_stack.core.costmap.raytrace_jit import ray_sample, ray_steps

F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]


@njit(cache=True)
def _integrate(log_odds: F32, seen: npt.NDArray[np.bool_], stamp: I64, width: int, height: int,
               origins: F64, ends: F64, keep_end: npt.NDArray[np.bool_], hit_cells: I64, starts: I64,
               hit_starts: I64, first_id: int, hit: np.float32, miss: np.float32, lo: np.float32,
               hi: np.float32) -> None:
    """Integrate scans s = 0..S-1 in order into the flat ``log_odds``/``seen`` (row-major, ``width``).

    Scan s: sensor at grid coordinates ``origins[s]``, rays to ``ends[starts[s]:starts[s+1]]`` (grid
    coordinates), each keeping its end cell where ``keep_end``; its endpoint cells are
    ``hit_cells[hit_starts[s]:hit_starts[s+1]]`` (flat). ``stamp`` (per cell) marks the cells a scan
    has touched: ``-(id)-1`` for its endpoints, ``id`` once updated, where id = ``first_id`` + s.
    """
    for s in range(len(starts) - 1):
        sid = first_id + s
        for j in range(hit_starts[s], hit_starts[s + 1]):
            stamp[hit_cells[j]] = -sid - 1
        ox, oy = origins[s, 0], origins[s, 1]
        for i in range(starts[s], starts[s + 1]):
            ex, ey = ends[i, 0], ends[i, 1]
            dx, dy = ex - ox, ey - oy
            steps = ray_steps(dx, dy)
            end_x, end_y = math.floor(ex), math.floor(ey)
            for k in range(steps + 1):
                _, px, py = ray_sample(ox, oy, dx, dy, k, steps)
                if not keep_end[i] and px == end_x and py == end_y:
                    continue
                if px < 0 or px >= width or py < 0 or py >= height:
                    continue
                c = py * width + px
                if stamp[c] == sid or stamp[c] == -sid - 1:
                    continue
                stamp[c] = sid
                log_odds[c] = max(log_odds[c] + miss, lo)
                seen[c] = True
        for j in range(hit_starts[s], hit_starts[s + 1]):
            c = hit_cells[j]
            if stamp[c] != sid:
                stamp[c] = sid
                log_odds[c] = min(log_odds[c] + hit, hi)
                seen[c] = True


def integrate(log_odds: F32, seen: npt.NDArray[np.bool_], stamp: I64, origins: F64, ends: F64,
              keep_end: npt.NDArray[np.bool_], hit_cells: I64, starts: I64, hit_starts: I64, first_id: int,
              update: tuple[np.float32, np.float32, np.float32, np.float32]) -> None:
    """Run the kernel on the 2D ``log_odds``/``seen`` (modified in place); ``update`` is (hit, miss,
    clamp low, clamp high) in log-odds. See ``_integrate`` for the other arguments."""
    height, width = log_odds.shape
    _integrate(log_odds.reshape(-1), seen.reshape(-1), stamp, width, height, origins, ends, keep_end,
               hit_cells, starts, hit_starts, first_id, *update)


def warm_up() -> None:
    """Compile (or load from the cache) the kernel now, on one ray across a 3 x 3 grid."""
    log_odds, seen = np.zeros((3, 3), dtype=np.float32), np.zeros((3, 3), dtype=bool)
    stamp = np.full(9, np.iinfo(np.int64).min, dtype=np.int64)
    one = np.array([0, 1], dtype=np.int64)
    integrate(log_odds, seen, stamp, np.array([[0.5, 0.5]]), np.array([[2.5, 2.5]]), np.zeros(1, dtype=bool),
              np.array([8], dtype=np.int64), one, one, 0,
              (np.float32(0.85), np.float32(-0.4), np.float32(-2.0), np.float32(3.5)))
