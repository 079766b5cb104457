"""Controller compute time per cycle: DWB (20×20 samples) and Regulated Pure Pursuit.

Setting: the Jazzy local costmap (3 m × 3 m, 0.05 m, robot at its centre) with an inflated
obstacle beside a straight 1.5 m path, robot moving at 0.2 m/s. Targets (brief): DWB ≤ 5 ms,
RPP ≤ 0.5 ms per cycle.

Run: ``.venv/bin/python -m bench.bench_control`` (``--no-record`` to only print).
"""

from __future__ import annotations

import os

import numpy as np

from bench.harness import Benchmark, parse_cli
from bench.worlds import inflate
from nav_stack.core.control import CostGrid, DWBController, RegulatedPurePursuit, Twist2D
from nav_stack.core.geometry import Pose2D, headings_along
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("control")
    spec = GridSpec(60, 60, 0.05, -1.5, -1.5)
    costs = np.zeros(spec.shape, np.uint8)
    costs[10:20, 36:42] = LETHAL_OBSTACLE  # a box 0.3–0.6 m ahead, 0.5–1.0 m to the right
    grid = CostGrid(inflate(costs, spec.resolution), spec)
    xy = np.column_stack((np.linspace(0.0, 1.45, 30), np.zeros(30)))
    path = np.column_stack((xy, headings_along(xy)))
    robot, vel = Pose2D(0.0, 0.05, 0.1), Twist2D(0.2, 0.1)

    dwb = DWBController()
    stats = bench.time(
        "DWB cycle (20x20 samples)",
        lambda: dwb.compute_velocity(robot, vel, path, grid),
        repeat=200,
        warmup=5,
    )
    bench.record(
        "DWB cycle (20x20 samples)",
        stats,
        "ms",
        scale=1e3,
        note=f"3 m local costmap, 7 critics, load {os.getloadavg()[0]:.1f}",
    )
    rpp = RegulatedPurePursuit()
    stats = bench.time(
        "RPP cycle", lambda: rpp.compute_velocity(robot, vel, path, grid), repeat=2000, warmup=20
    )
    bench.record(
        "RPP cycle",
        stats,
        "ms",
        scale=1e3,
        note=f"collision check up to the carrot on, load {os.getloadavg()[0]:.1f}",
    )
    bench.save()


if __name__ == "__main__":
    main()
