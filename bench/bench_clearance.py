"""sim2d's ground-truth clearance (sim2d/core/clearance.py): what one evaluation costs against a physics
step, and so whether it can run every physics step or only with each odometry message.

Measured in turtlebot3_world (54 obstacle edges, 9 pillars) and depot_large (232 edges), the waffle
driving a slow arc; the ratio is clearance / physics step from the same run. Per simulated second the
node would spend 200 evaluations at every physics step (5 ms) against 30 at the odometry rate.

Run: .venv/bin/python -m bench.bench_clearance [--no-record]
"""

from __future__ import annotations

import os

import numpy as np

from bench.harness import Benchmark, parse_cli
from sim2d.core.clearance import simulator_clearance
from sim2d.core.robot import WAFFLE, Pose2D
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import load_world

ODOMETRY_RATE = 30.0  # Hz, sim2d's default odometry.rate


def bench_world(bench: Benchmark, world_name: str) -> None:
    world = load_world(world_name)
    spawn = Pose2D(*world.spawns[0]) if world.spawns else Pose2D(-2.0, -0.5, 0.0)
    sim = Simulator(world, WAFFLE, SimParams(initial_pose=spawn), np.random.default_rng(0))

    def step() -> None:
        sim.command(0.1, 0.3)
        sim.step()

    physics = bench.time(f"physics step ({world_name})", step, repeat=3000, warmup=100)
    clearance = bench.time(f"clearance ({world_name})", lambda: simulator_clearance(sim), repeat=3000,
                           warmup=100)
    load = os.getloadavg()[0]
    geometry = sim.lidar.geometry
    bench.record(f"clearance per call ({world_name})", clearance, "µs", scale=1e6,
                 note=f"{len(geometry.ray_segments)} edges, {len(geometry.circles)} circles; load {load:.1f}")
    bench.record(f"physics step ({world_name}, same run)", physics, "µs", scale=1e6, note=f"load {load:.1f}")
    bench.record_value(f"clearance / physics step ({world_name})", clearance.median / physics.median, "x",
                       note="medians of the same run")
    steps = round(1.0 / sim.params.physics_step)
    bench.record_value(f"clearance CPU per sim second, every physics step ({world_name})",
                       steps * clearance.median * 1e3, "ms", note=f"{steps} evaluations")
    bench.record_value(f"clearance CPU per sim second, odometry rate ({world_name})",
                       ODOMETRY_RATE * clearance.median * 1e3, "ms", note=f"{ODOMETRY_RATE:g} evaluations")


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("clearance")
    for world_name in ("turtlebot3_world", "depot_large"):
        bench_world(bench, world_name)
    bench.save()


if __name__ == "__main__":
    main()
