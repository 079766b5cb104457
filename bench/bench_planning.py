"""Global planning time: NavFn-style grid A* / Dijkstra and Theta* on the TB3 world and a 1000×1000 map.

Targets (brief): ≤ 10 ms median on the 384×384 TB3 map, ≤ 150 ms on 1000×1000 (50 m × 50 m at
0.05 m with 100 random boxes/discs inflated like the TB3 map; 16 % of cells carry cost; start and
goal ≥ 35 m apart). "warm" = the
planner's prepared graph is reused (costmap unchanged since the last plan, the usual case at a
1 Hz global costmap); "cold" includes translating the costmap (first plan after an update).

Issue 19's 2000 x 2000 map is planned twice, through the compiled search (what the planner uses)
and through the pure-Python reference it is checked against, and the ratio is recorded.

Run: ``.venv/bin/python -m bench.bench_planning`` (``--no-record`` to only print).
"""

from __future__ import annotations

import contextlib
import os

import numpy as np

from bench.harness import Benchmark
from bench.worlds import random_obstacle_costmap, turtlebot3_world_costmap
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning import (
    NavfnParams,
    NavfnPlanner,
    PlanningError,
    ThetaStarPlanner,
    grid_search,
    grid_search_jit,
    theta_star,
)

U8 = np.ndarray


def seeded_pairs(
    costs: U8, spec: GridSpec, n: int, min_dist: float, seed: int
) -> list[tuple[Pose2D, Pose2D]]:
    """Start/goal pairs on cells of cost < 128 at least ``min_dist`` m apart."""
    rng = np.random.default_rng(seed)
    free = np.argwhere(costs < 128)
    pairs: list[tuple[Pose2D, Pose2D]] = []
    while len(pairs) < n:
        (ay, ax), (by, bx) = free[rng.integers(len(free), size=2)]
        (sx, gx), (sy, gy) = spec.cell_to_world(np.array([ax, bx]), np.array([ay, by]))
        if np.hypot(gx - sx, gy - sy) >= min_dist:
            pairs.append((Pose2D(float(sx), float(sy), 0.0), Pose2D(float(gx), float(gy), 0.0)))
    return pairs


def time_pairs(
    bench: Benchmark,
    label: str,
    planner: NavfnPlanner | ThetaStarPlanner,
    costs: U8,
    spec: GridSpec,
    pairs: list[tuple[Pose2D, Pose2D]],
    cold: bool = False,
) -> float:
    """Time one plan per pair (the first is a warm-up) and record the row; the median in s."""
    it = iter(pairs)

    def plan() -> None:
        start, goal = next(it)
        # cold: a fresh planner re-translates the costmap, as after a costmap update
        used = NavfnPlanner(planner.params) if cold and isinstance(planner, NavfnPlanner) else planner
        with contextlib.suppress(PlanningError):
            used.create_plan(start, goal, costs, spec)

    stats = bench.time(label, plan, repeat=len(pairs) - 1, warmup=1)
    bench.record(
        label,
        stats,
        "ms",
        scale=1e3,
        note=f"{len(pairs) - 1} seeded start/goal pairs, load {os.getloadavg()[0]:.1f}",
    )
    return stats.median


def main() -> None:
    bench = Benchmark("planning")
    costs, spec, source = turtlebot3_world_costmap()
    print(f"TB3 world: {source}, inflated r 0.22 / 0.70 / csf 3")
    pairs = seeded_pairs(costs, spec, 101, 1.0, seed=1)
    time_pairs(
        bench,
        "TB3 384x384 GridBased A* (warm)",
        NavfnPlanner(NavfnParams(use_astar=True)),
        costs,
        spec,
        pairs,
    )
    time_pairs(
        bench,
        "TB3 384x384 GridBased A* (cold)",
        NavfnPlanner(NavfnParams(use_astar=True)),
        costs,
        spec,
        pairs,
        cold=True,
    )
    time_pairs(
        bench,
        "TB3 384x384 GridBased Dijkstra (warm)",
        NavfnPlanner(NavfnParams(use_astar=False)),
        costs,
        spec,
        pairs,
    )
    theta = time_pairs(bench, "TB3 384x384 Theta*", ThetaStarPlanner(), costs, spec, pairs[:31])
    theta_reference = time_pairs(bench, "TB3 384x384 Theta* (reference search)",
                                 ThetaStarPlanner(search=theta_star.search), costs, spec, pairs[:31])
    bench.record_value("TB3 384x384 Theta*: reference / compiled (medians)", theta_reference / theta, "x",
                       "same pairs, same run")

    big, big_spec = random_obstacle_costmap(1000, seed=2, n_obstacles=100)
    big_pairs = seeded_pairs(big, big_spec, 11, 35.0, seed=3)
    time_pairs(
        bench,
        "1000x1000 GridBased A* (warm)",
        NavfnPlanner(NavfnParams(use_astar=True)),
        big,
        big_spec,
        big_pairs,
    )
    time_pairs(
        bench,
        "1000x1000 GridBased A* (cold)",
        NavfnPlanner(NavfnParams(use_astar=True)),
        big,
        big_spec,
        big_pairs,
        cold=True,
    )
    time_pairs(
        bench,
        "1000x1000 GridBased Dijkstra (warm)",
        NavfnPlanner(NavfnParams(use_astar=False, max_planning_time=30.0)),
        big,
        big_spec,
        big_pairs[:4],
    )
    compiled_against_reference(bench)
    bench.save()


def compiled_against_reference(bench: Benchmark) -> None:
    """Issue 19's map, side by side in one run: 2000 x 2000 at 5 cm (100 m x 100 m, 1600 obstacles,
    six seeded pairs more than 20 m apart), the same plans through the compiled search and through
    the pure-Python reference; the ratio of the medians is recorded."""
    big, big_spec = random_obstacle_costmap(2000, seed=2, n_obstacles=1600)
    pairs = seeded_pairs(big, big_spec, 7, 20.0, seed=3)
    for algorithm, astar in (("A*", True), ("Dijkstra", False)):
        medians = {}
        for name, search in (("compiled", grid_search_jit.search), ("reference", grid_search.search)):
            params = NavfnParams(use_astar=astar, max_planning_time=60.0, max_iterations=10**7)
            label = f"2000x2000 GridBased {algorithm} (warm, {name} search)"
            medians[name] = time_pairs(bench, label, NavfnPlanner(params, search=search), big, big_spec,
                                       pairs)
        bench.record_value(f"2000x2000 GridBased {algorithm}: reference / compiled (medians)",
                           medians["reference"] / medians["compiled"], "x", "same pairs, same run")


if __name__ == "__main__":
    main()
