"""Costmap update times: a local rolling costmap per scan and full / incremental global inflation.

* local: Jazzy local costmap (odom, 3 m × 3 m rolling window at 0.05 m, obstacle + inflation,
  robot_radius 0.22, inflation 0.70, csf 3.0); each call feeds one 360-beam scan and moves the robot
  by about one cell, so the window shifts and is redrawn (the steady state while driving).
* global full: a 2000 × 2000 map (100 m at 0.05 m) with random boxes, static + inflation, first
  update after the map arrives (whole-map inflation). Nav2 docs quote 48.9 ms single-thread in C++
  for a 2000 × 2000 grid with a 2 m radius (Kilted+).
* global incremental: the same map, one 360-beam scan into the obstacle layer; only the touched
  window (plus two inflation radii) is recomputed.

* warehouse (issue 44): a 1700 x 1000 map at 3 cm (the size of bench_large_world's office), static +
  obstacle + inflation, one 1 Hz global update holding six queued 360-beam TB4 scans (12 m, 30 % no
  return) from a robot standing still: the steady state between goals, where the obstacle layer now
  reports only the cells that changed. Publishing it: the OccupancyGrid values of the whole grid as
  before issue 44 (grid.occupancy_from_cost), by Nav2's table (publish.occupancy_of), and by the table
  on a 3 m window (a costmap_updates message), in the same run.

Inflation and ray clearing run compiled (inflation_jit, raytrace_jit), as the costmap nodes run them;
the global updates are also timed with the numpy reference inflation (inflation_layer.inflate), and the
local one with the numpy reference ray clearing (raytrace.clear_rays), in the same run, and the ratios
of the medians recorded, since absolute times follow the machine's load (noted in each row).

Run: ``.venv/bin/python -m bench.bench_costmap`` (``--no-record`` to only print).
"""

from __future__ import annotations

import math
import os

import numpy as np

from bench.harness import Benchmark, parse_cli
from nav_stack.core.costmap import (
    CostmapParams,
    InflationLayer,
    LaserScan,
    LayeredCostmap,
    ObstacleLayer,
    StaticLayer,
    raytrace,
)
from nav_stack.core.costmap.inflation_layer import Inflate, inflate
from nav_stack.core.costmap.layer import Window
from nav_stack.core.costmap.params import InflationLayerParams
from nav_stack.core.costmap.publish import occupancy_of
from nav_stack.core.costmap.raytrace import ClearRays
from nav_stack.core.grid import GridSpec, occupancy_from_cost


def random_map(size: int, boxes: int, seed: int) -> tuple[np.ndarray, GridSpec]:
    spec = GridSpec(size, size, 0.05)
    rng = np.random.default_rng(seed)
    occ = np.zeros(spec.shape, dtype=np.int8)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = 100
    for _ in range(boxes):
        x, y = rng.integers(0, size - 40, 2)
        w, h = rng.integers(2, 40, 2)
        occ[y : y + h, x : x + w] = 100
    return occ, spec


def ring_scan(radius: float) -> LaserScan:
    ranges = np.full(360, radius) + 0.3 * np.sin(np.arange(360) * 0.1)
    return LaserScan(ranges, 0.0, 2 * math.pi / 360, 0.12, 3.5)


def load_note(note: str = "") -> str:
    return ", ".join(part for part in (note, f"load {os.getloadavg()[0]:.1f}") if part)


def local_costmap(bench: Benchmark, clear_rays: ClearRays | None, suffix: str = "") -> float:
    """Rolling local costmap updates, one scan each; their median (s).

    ``clear_rays``: None for the compiled ray clearing, or the reference; ``suffix`` names it in the rows.
    """
    local_params = CostmapParams.local_defaults()
    obstacle = ObstacleLayer(local_params, clear_rays=clear_rays)
    local = LayeredCostmap(local_params, [obstacle, InflationLayer()])
    scan = ring_scan(1.2)
    step = [0]

    def local_update() -> None:
        step[0] += 1
        pose = (0.05 * step[0], 0.02 * step[0], 0.0)
        obstacle.add_scan(scan, pose)
        local.update(pose)

    stats = bench.time(f"local costmap update per scan{suffix}", local_update, repeat=200, warmup=10)
    bench.record(f"local costmap update per scan (3x3 m, 360 beams, rolling){suffix}", stats, "ms", 1e3,
                 load_note())
    return stats.median


def global_costmap(bench: Benchmark, inflation: Inflate | None, suffix: str = "") -> tuple[float, float]:
    """Full and incremental updates of the 2000 x 2000 global costmap; their medians (s).

    ``inflation``: None for the compiled inflation, or the reference; ``suffix`` names it in the rows.
    """
    occ, spec = random_map(2000, 3000, seed=1)
    params = CostmapParams()

    def full_global() -> None:
        costmap = LayeredCostmap(params, [StaticLayer(params), InflationLayer(inflate=inflation)])
        costmap.set_map(occ, spec)
        costmap.update((50.0, 50.0, 0.0))

    full = bench.time(f"global 2000x2000 full inflation{suffix}", full_global, repeat=10, warmup=1)
    lethal = f"{int((occ == 100).mean() * 100)} % lethal cells"
    bench.record(f"global 2000x2000 full update (static + inflation 0.7 m){suffix}", full, "ms", 1e3,
                 load_note(lethal))

    g_obstacle = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [StaticLayer(params), g_obstacle, InflationLayer(inflate=inflation)])
    costmap.set_map(occ, spec)
    costmap.update((50.0, 50.0, 0.0))
    scan = ring_scan(1.2)

    def incremental() -> None:
        g_obstacle.add_scan(scan, (50.0, 50.0, 0.0))
        costmap.update((50.0, 50.0, 0.0))

    inc = bench.time(f"global 2000x2000 incremental scan update{suffix}", incremental, repeat=50, warmup=3)
    bench.record(f"global 2000x2000 incremental update per scan (static+obstacle+inflation){suffix}", inc,
                 "ms", 1e3, load_note())
    return full.median, inc.median


def warehouse(bench: Benchmark) -> None:
    """The warehouse-sized global costmap's update and publication costs (see the module doc)."""
    occ, _ = random_map(1700, 2000, seed=1)
    occ = np.ascontiguousarray(occ[:1000, :])
    spec = GridSpec(1700, 1000, 0.03)
    params = CostmapParams(resolution=0.03, robot_radius=0.175)
    obstacle = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [StaticLayer(params), obstacle,
                                      InflationLayer(InflationLayerParams(inflation_radius=0.7))])
    costmap.set_map(occ, spec)
    pose = (25.0, 15.0, 0.0)
    costmap.update(pose)
    rng = np.random.default_rng(3)
    scans = []
    for _ in range(6):
        ranges = rng.uniform(0.5, 12.0, 360)
        ranges[rng.random(360) < 0.3] = np.inf
        scans.append(LaserScan(ranges, 0.0, 2 * math.pi / 360, 0.15, 12.0))

    def one_update() -> None:
        for scan in scans:
            obstacle.add_scan(scan, pose)
        costmap.update(pose)

    stats = bench.time("warehouse global update", one_update, repeat=30, warmup=2)
    bench.record("warehouse 1700x1000 at 3 cm: global update with 6 queued TB4 scans, robot standing", stats,
                 "ms", 1e3, load_note())
    costs = costmap.costs
    window = Window(750, 400, 950, 600)  # 6 m x 6 m: one scan's clearing range of 3 m around the robot
    timings = {
        "whole grid, per-cell arithmetic (before issue 44)": lambda: occupancy_from_cost(costs),
        "whole grid, translation table": lambda: occupancy_of(costs),
        "6x6 m window, translation table": lambda: occupancy_of(costs[window.slices]),
    }
    medians = {}
    for label, convert in timings.items():
        result = bench.time(f"occupancy values, {label}", convert, repeat=30, warmup=2)
        bench.record(f"warehouse 1700x1000: OccupancyGrid values of the {label}", result, "ms", 1e3,
                     load_note())
        medians[label] = result.median
    first, second, _ = timings
    bench.record_value("warehouse 1700x1000: OccupancyGrid values, arithmetic / table (whole grid, medians)",
                       medians[first] / medians[second], "x", "same grid, same run")


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("costmap")
    warehouse(bench)
    local_fast = local_costmap(bench, None)
    local_ref = local_costmap(bench, raytrace.clear_rays, ", numpy reference ray clearing")
    bench.record_value("local costmap update per scan: reference / compiled ray clearing (medians)",
                       local_ref / local_fast, "x", "same scans, same run")
    compiled = global_costmap(bench, None)
    reference = global_costmap(bench, inflate, ", numpy reference inflation")
    for update, ref, fast in zip(("full update", "incremental update"), reference, compiled, strict=True):
        bench.record_value(f"global 2000x2000 {update}: reference / compiled (medians)", ref / fast, "x",
                           "same map, same run")
    bench.save()


if __name__ == "__main__":
    main()
