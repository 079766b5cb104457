"""sim2d fleets (issue 48): what N robots in one world cost the core, per physics step and per scan.

Fleets of 1, 3 and 5 TB4s (12 m RPLIDAR, the costly sensor) in depot_large, spread along the hall
2.5 m apart so that each sees the others, every robot turning on a tight arc (0.05 m/s, 0.5 rad/s).
2.5 m is beyond fleet.REACH_SLACK, so the robots' bodies in each other's collision space stay put:
the spread case; robots within reach re-index each other's bodies every step (about 5 µs a pair).
Per fleet: one fleet physics step, the fleet's physics steps per second, one lidar scan of robot1
(the same pose in every fleet, so what grows is the cost of casting the others' bodies), and one
simulated second with the default schedule (200 physics steps and a 5 Hz scan per robot) as a
real-time factor. Ratios, from medians of the same run: the step per robot of 3 and 5 robots
against 1, and a one-robot fleet's step against a lone Simulator's (the fleet's own overhead; both
run the same RobotSim code).

Run: .venv/bin/python -m bench.bench_fleet [--no-record]
"""

from __future__ import annotations

import os

import numpy as np

from bench.harness import Benchmark, parse_cli
from sim2d.core.fleet import Fleet, FleetRobot
from sim2d.core.robot import TB4, Pose2D
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import World, load_world

HALL = [Pose2D(x, 0.051, 0.0) for x in (-14.2, -11.7, -9.2, -4.2, -1.7)]   # free hall poses of depot_large
COMMAND = (0.05, 0.5)   # m/s, rad/s: a 0.1 m radius arc that keeps each robot clear of walls and others
SCAN_EVERY = 40         # physics steps of 5 ms: a 5 Hz scan


def _fleet(world: World, robots: int) -> Fleet:
    declared = [FleetRobot(f"robot{i + 1}", TB4, HALL[i]) for i in range(robots)]
    return Fleet(world, declared, SimParams(), np.random.default_rng(0))


def bench_fleet(bench: Benchmark, world: World, robots: int) -> float:
    """Record one fleet size's figures; return the median fleet step (s)."""
    fleet = _fleet(world, robots)
    sims = list(fleet.robots.values())

    def step() -> None:
        for sim in sims:
            sim.command(*COMMAND)
        fleet.step()

    label = f"{robots} TB4 in depot_large"
    stats = bench.time(f"fleet physics step, {label}", step, repeat=3000, warmup=100)
    bench.record(f"fleet physics step, {label}", stats, "µs", scale=1e6)
    bench.record_value(f"fleet physics steps per second, {label}", 1.0 / stats.median, "steps/s")
    scan = bench.time(f"fleet lidar scan of one robot, {label}", lambda: fleet.scan("robot1"), repeat=500,
                      warmup=10)
    bench.record(f"fleet lidar scan of one robot, {label}", scan, "µs", scale=1e6,
                 note=f"360 beams, 12 m, {robots - 1} other robots cast too, load {os.getloadavg()[0]:.1f}")
    steps_per_second = round(1.0 / fleet.params.physics_step)

    def one_sim_second() -> None:
        for k in range(steps_per_second):
            step()
            if k % SCAN_EVERY == 0:
                for name in fleet.robots:
                    fleet.scan(name)

    second = bench.time(f"1 s of sim time, {label}", one_sim_second, repeat=10, warmup=1)
    bench.record_value(f"fleet core real-time factor (physics + 5 Hz lidar each), {label}",
                       1.0 / second.median, "x")
    return stats.median


def bench_lone(bench: Benchmark, world: World) -> float:
    """A lone Simulator at the first hall pose, as the fleet's robot1 drives: the median step (s)."""
    sim = Simulator(world, TB4, SimParams(initial_pose=HALL[0]), np.random.default_rng(0))

    def step() -> None:
        sim.command(*COMMAND)
        sim.step()

    stats = bench.time("lone Simulator physics step, TB4 in depot_large", step, repeat=3000, warmup=100)
    bench.record("lone Simulator physics step, TB4 in depot_large", stats, "µs", scale=1e6)
    return stats.median


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("sim2d_fleet")
    world = load_world("depot_large")
    lone = bench_lone(bench, world)
    steps = {robots: bench_fleet(bench, world, robots) for robots in (1, 3, 5)}
    bench.record_value("fleet of 1 / lone Simulator, physics step (medians)", steps[1] / lone, "x",
                       "the fleet's own overhead; same run")
    for robots in (3, 5):
        bench.record_value(f"fleet physics step per robot, {robots} robots / 1 robot (medians)",
                           steps[robots] / robots / steps[1], "x", "same run")
    bench.save()


if __name__ == "__main__":
    main()
