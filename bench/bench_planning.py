"""Global planning time: NavFn-style grid A* / Dijkstra and Theta* on the TB3 world and a 1000×1000 map.

Targets (brief): ≤ 10 ms median on the 384×384 TB3 map, ≤ 150 ms on 1000×1000 (50 m × 50 m at
0.05 m with 100 random boxes/discs inflated like the TB3 map; 16 % of cells carry cost; start and
goal ≥ 35 m apart). "warm" = the
planner's prepared graph is reused (costmap unchanged since the last plan, the usual case at a
1 Hz global costmap); "cold" includes translating the costmap (first plan after an update).

Issue 19's large maps (see :func:`large_maps`): a 2000 x 2000 map at 5 cm and a warehouse at 3 cm,
planned by the default planner (config/nav2_params.yaml), A*, the pure-Python reference search and,
side by side on the same costs and pairs, pyastar2d (a C++ A* on PyPI), the compiled baseline.
pyastar2d is for this benchmark only: ``.venv/bin/pip install --group bench`` (pyproject.toml's
``bench`` group); without it the baseline rows are skipped with that instruction.

Run: ``.venv/bin/python -m bench.bench_planning`` (``--no-record`` to only print).
"""

from __future__ import annotations

import collections
import dataclasses
import importlib
import os
from pathlib import Path
from types import ModuleType

import numpy as np
import numpy.typing as npt
import yaml

from bench.harness import Benchmark, parse_cli
from bench.worlds import random_obstacle_costmap, turtlebot3_world_costmap, warehouse_costmap
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
from nav_stack.core.planning.grid_search import navfn_cost_table

U8 = np.ndarray
NAV2_PARAMS = Path(__file__).resolve().parent.parent / "config" / "nav2_params.yaml"
PYASTAR2D_MISSING = (
    "bench_planning: pyastar2d is not installed, so the compiled baseline (issue 19) is skipped.\n"
    "  Install the benchmark group:  .venv/bin/pip install --group bench  (pip >= 25.1, in the repo root)\n"
    "  or only the package:          .venv/bin/pip install 'pyastar2d>=1.1'"
)


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
    """Time one plan per pair (the first is a warm-up) and record the row; the median in s.

    A plan that fails is timed all the same, and the row's note counts the failures by error code:
    a time that ends in TIMEOUT or NO_VALID_PATH is not a planning time."""
    it = iter(pairs)
    failures: collections.Counter[str] = collections.Counter()

    def plan() -> None:
        start, goal = next(it)
        # cold: a fresh planner re-translates the costmap, as after a costmap update
        used = NavfnPlanner(planner.params) if cold and isinstance(planner, NavfnPlanner) else planner
        try:
            used.create_plan(start, goal, costs, spec)
        except PlanningError as exc:
            failures[exc.code.name] += 1

    stats = bench.time(label, plan, repeat=len(pairs) - 1, warmup=1)
    failed = ", ".join(f"{n} {code}" for code, n in sorted(failures.items()))
    bench.record(
        label,
        stats,
        "ms",
        scale=1e3,
        note=f"{len(pairs) - 1} seeded start/goal pairs, load {os.getloadavg()[0]:.1f}"
        + (f", FAILED (warm-up included): {failed}" if failed else ""),
    )
    return stats.median


def main() -> None:
    parse_cli(__doc__)
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
    large_maps(bench)
    bench.save()


def default_navfn_params(**overrides: float) -> NavfnParams:
    """NavfnPlanner as config/nav2_params.yaml configures GridBased (its use_astar decides the search)."""
    doc = yaml.safe_load(NAV2_PARAMS.read_text())
    grid_based = doc["planner_server"]["ros__parameters"]["GridBased"]
    knobs = {f.name for f in dataclasses.fields(NavfnParams)}
    return NavfnParams(**{**{k: v for k, v in grid_based.items() if k in knobs}, **overrides})


def load_pyastar2d() -> ModuleType | None:
    """pyastar2d (the compiled baseline), or None with the instructions to install it."""
    try:
        return importlib.import_module("pyastar2d")
    except ImportError:
        print(PYASTAR2D_MISSING, flush=True)
        return None


def pyastar2d_weights(costs: U8, allow_unknown: bool) -> npt.NDArray[np.float32]:
    """NavFn's traversal cost per cell divided by its neutral cost 50: 1 + 0.016·c below 253, 253/50 for
    unknown (allowed), inf where NavFn cannot pass. pyastar2d needs every weight ≥ 1, which this is.

    The per-cell costs are then exactly NavFn's up to the factor 50; what still differs is the metric:
    pyastar2d charges a diagonal step the entered cell's weight, NavFn √2 times it, so its paths may
    run diagonal where ours run straight (path costs are not compared, only times)."""
    table = np.asarray(navfn_cost_table(allow_unknown)) / grid_search.NEUTRAL_COST
    return table.astype(np.float32)[costs]


def time_pyastar2d(bench: Benchmark, label: str, pyastar2d: ModuleType, costs: U8, spec: GridSpec,
                   pairs: list[tuple[Pose2D, Pose2D]], allow_unknown: bool) -> float:
    """Time pyastar2d on the pairs' start and goal cells (same warm-up and count as time_pairs); the
    median in s. The weights are prepared once, as our warm planner reuses its prepared graph."""
    weights = pyastar2d_weights(costs, allow_unknown)
    it = iter(pairs)

    def plan() -> None:
        start, goal = next(it)
        (sx, gx), (sy, gy) = spec.world_to_cell(np.array([start.x, goal.x]), np.array([start.y, goal.y]))
        pyastar2d.astar_path(weights, (int(sy), int(sx)), (int(gy), int(gx)), allow_diagonal=True)

    stats = bench.time(label, plan, repeat=len(pairs) - 1, warmup=1)
    bench.record(label, stats, "ms", scale=1e3,
                 note=f"{len(pairs) - 1} pairs as above, weights 1 + 0.016·c (NavFn / 50), "
                      f"load {os.getloadavg()[0]:.1f}")
    return stats.median


def large_maps(bench: Benchmark) -> None:
    """Issue 19's maps, planned side by side in one run on the same costs and pairs.

    - 2000 x 2000 at 5 cm (100 m x 100 m, 1600 obstacles, six seeded pairs more than 20 m apart):
      the default planner (nav2_params.yaml), A* and Dijkstra through the compiled search
      and through the pure-Python reference it is checked against, and pyastar2d;
    - a warehouse at 3 cm (1000 x 1667 cells, racks and aisles, six pairs more than 20 m apart): the
      default planner, the other of A* and Dijkstra, and pyastar2d.

    Ratios of medians: reference / compiled, and our planner / pyastar2d (the issue's target: the
    default planner within 3x of it, and within 50 ms)."""
    pyastar2d = load_pyastar2d()
    big, big_spec = random_obstacle_costmap(2000, seed=2, n_obstacles=1600)
    pairs = seeded_pairs(big, big_spec, 7, 20.0, seed=3)
    medians: dict[str, float] = {}
    for algorithm, astar in (("A*", True), ("Dijkstra", False)):
        for name, search in (("compiled", grid_search_jit.search), ("reference", grid_search.search)):
            label = f"2000x2000 GridBased {algorithm} (warm, {name} search)"
            # the reference takes seconds: no timeout
            params = NavfnParams(use_astar=astar, max_planning_time=60.0, max_iterations=10**7)
            planner = NavfnPlanner(params, search=search)
            medians[f"{algorithm} {name}"] = time_pairs(bench, label, planner, big, big_spec, pairs)
        bench.record_value(f"2000x2000 GridBased {algorithm}: reference / compiled (medians)",
                           medians[f"{algorithm} reference"] / medians[f"{algorithm} compiled"], "x",
                           "same pairs, same run")
    warehouse, warehouse_spec = warehouse_costmap(seed=4)
    warehouse_pairs = seeded_pairs(warehouse, warehouse_spec, 7, 20.0, seed=5)
    cases = (("2000x2000", big, big_spec, pairs),
             (f"warehouse {warehouse_spec.width}x{warehouse_spec.height} at 3 cm", warehouse, warehouse_spec,
              warehouse_pairs))
    shipped = default_navfn_params()
    default_name, other_name = ("A*", "Dijkstra") if shipped.use_astar else ("Dijkstra", "A*")
    for name, costs, spec, map_pairs in cases:
        default = time_pairs(bench, f"{name} GridBased default (nav2_params.yaml: {default_name}, warm)",
                             NavfnPlanner(shipped), costs, spec, map_pairs)
        other = time_pairs(bench, f"{name} GridBased {other_name} (warm)",
                           NavfnPlanner(default_navfn_params(use_astar=not shipped.use_astar)), costs, spec,
                           map_pairs)
        if pyastar2d is None:
            continue
        baseline = time_pyastar2d(bench, f"{name} pyastar2d (C++ A*, compiled baseline)", pyastar2d, costs,
                                  spec, map_pairs, shipped.allow_unknown)
        for which, median in ((f"default ({default_name})", default), (other_name, other)):
            bench.record_value(f"{name} GridBased {which} / pyastar2d (medians)", median / baseline, "x",
                               "same pairs, same costs, same run")
    if pyastar2d is None:
        print(PYASTAR2D_MISSING, flush=True)


if __name__ == "__main__":
    main()
