"""Compile the numba kernels once, at setup, into their ``__pycache__`` (``@njit(cache=True)``).

Why at setup: on a fresh checkout the first process to build a planner or a costmap compiles its
kernels, which takes seconds (more on a loaded machine). Inside a running stack that is seconds in
which a node's lifecycle transition, and on a busy CI machine a test's readiness wait, stand still.
Done here, every later process only loads the cached machine code (well under a second). When the
cache is current this takes about a second; numba recompiles by itself when a kernel's source changes.

Usage: .venv/bin/python scripts/compile_kernels.py
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ProcessPoolExecutor

from nav_stack.core.control.mppi import kernels_jit as mppi_kernels_jit
from nav_stack.core.costmap import inflation_jit, raytrace_jit
from nav_stack.core.planning import grid_search_jit, theta_star_jit
from nav_stack.core.slam import integrate_jit, pose_graph_jit
from sim2d.core import lidar_jit

KERNELS = {  # the slowest first, so that it starts at once in a pool
    "SLAM pose-graph solve": pose_graph_jit.warm_up,
    "MPPI controller (rollout, critics, noise)": mppi_kernels_jit.warm_up,
    "grid search (NavFn A*/Dijkstra)": grid_search_jit.warm_up,
    "Theta*": theta_star_jit.warm_up,
    "costmap inflation": inflation_jit.warm_up,
    "costmap ray clearing": raytrace_jit.warm_up,
    "SLAM map update": integrate_jit.warm_up,
    "sim2d lidar (binned ray casting)": lidar_jit.warm_up,
}


def _warm_up(name: str) -> None:
    KERNELS[name]()


def main() -> int:
    """Compile the kernels in parallel, one process per core: each kernel has its own cache files,
    and the pose-graph solve alone takes most of the time (8 s of 12 s from scratch, 2026-11-28)."""
    started = time.monotonic()
    workers = min(len(KERNELS), os.cpu_count() or 1)
    if workers > 1:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            list(pool.map(_warm_up, KERNELS))  # list(): re-raises a kernel's compile error here
    else:
        for name in KERNELS:
            _warm_up(name)
    print(f"setup: compiled kernels ready ({', '.join(KERNELS)}) in {time.monotonic() - started:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
