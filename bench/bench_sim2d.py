"""sim2d speed: core physics and lidar steps per second, and the node's real-time factor in max mode.

Core: one physics step (waffle driving an arc in turtlebot3_world), one 360-beam scan, and one
simulated second with the default schedule (200 physics steps + 5 scans), reported as a
real-time factor. Large worlds (issue 44): one TB4 scan (360 beams, 12 m) from random free poses of
depot_large and of a generated 45 x 30 m office (the warehouse of bench_large_world, seed 3), cast by
the compiled caster (lidar_jit, what the simulator runs) and by the numpy reference (lidar.cast_rays)
in the same run, and the ratio of their medians. Node: ``python -m sim2d.ros.cli --rtf max`` in a
child process publishing everything over DDS; this process reads ``sim2d/real_time_factor``
(achieved, per wall second), first with no other subscriber, then while subscribing to /scan, /odom,
/tf and /clock.

Run: .venv/bin/python -m bench.bench_sim2d [--no-record]
"""

from __future__ import annotations

import itertools
import math
import os
import statistics
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import yaml

from bench.harness import Benchmark, parse_cli
from sim2d.core.geometry import StaticGeometry
from sim2d.core.lidar import RPLIDAR_A1, Caster, cast_rays
from sim2d.core.lidar_jit import BinnedCaster
from sim2d.core.office_world import generate_office
from sim2d.core.robot import WAFFLE
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import load_world


def bench_core(bench: Benchmark) -> None:
    sim = Simulator(load_world("turtlebot3_world"), WAFFLE, SimParams(), np.random.default_rng(0))

    def step() -> None:
        sim.command(0.1, 0.3)   # a slow circle that stays clear of obstacles
        sim.step()

    stats = bench.time("physics step", step, repeat=5000, warmup=100)
    bench.record("physics step", stats, "µs", scale=1e6, note="waffle, turtlebot3_world, arc")
    bench.record_value("physics steps per second", 1.0 / stats.median, "steps/s")
    scan = bench.time("lidar scan", sim.scan, repeat=500, warmup=10)
    bench.record("lidar scan (360 beams)", scan, "µs", scale=1e6)
    steps_per_second = round(1.0 / sim.params.physics_step)

    def one_sim_second() -> None:
        for k in range(steps_per_second):
            step()
            if k % (steps_per_second // 5) == 0:
                sim.scan()

    second = bench.time("1 s of sim time (core)", one_sim_second, repeat=20, warmup=2)
    bench.record_value("core real-time factor (physics + 5 Hz lidar)", 1.0 / second.median, "x")


def _office_geometry() -> StaticGeometry:
    """The 45 x 30 m office of bench_large_world (seed 3), loaded as the simulator loads it."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "office_45x30_seed3.yaml"
        path.write_text(yaml.safe_dump(generate_office(45.0, 30.0, 3).world("office_45x30_seed3")))
        return load_world(path).geometry


def _scan_timer(caster: Caster, geometry: StaticGeometry, poses: list[np.ndarray]) -> Callable[[], None]:
    """One TB4 scan per call, from the next of ``poses`` in turn."""
    angles = np.linspace(0.0, 2.0 * math.pi, RPLIDAR_A1.beams, endpoint=False) + 0.1
    reach = RPLIDAR_A1.range_max + 4.0 * RPLIDAR_A1.noise_stddev
    turn = itertools.cycle(poses)

    def one_scan() -> None:
        x, y = next(turn)
        caster((float(x), float(y)), angles, geometry, reach)

    return one_scan


def bench_large_world_lidar(bench: Benchmark) -> None:
    """Compiled vs reference casting of a TB4 scan on the two large worlds (see the module doc)."""
    worlds = (("depot_large", load_world("depot_large").geometry), ("office 45x30", _office_geometry()))
    for name, geometry in worlds:
        rng = np.random.default_rng(1)
        low, high = geometry.ray_segments[:, :2].min(axis=0), geometry.ray_segments[:, :2].max(axis=0)
        poses = [p for p in rng.uniform(low, high, size=(200, 2)) if not geometry.contains(p[None])[0]][:50]
        medians = {}
        compiled: Caster = BinnedCaster()
        for label, caster in (("compiled", compiled), ("numpy reference", cast_rays)):
            stats = bench.time(f"{name} lidar scan ({label})", _scan_timer(caster, geometry, poses),
                               repeat=300, warmup=5)
            note = (f"{len(geometry.ray_segments)} segments, {len(poses)} free poses, "
                    f"load {os.getloadavg()[0]:.1f}")
            bench.record(f"lidar scan, TB4 360 beams 12 m, {name} ({label})", stats, "µs", scale=1e6,
                         note=note)
            medians[label] = stats.median
        bench.record_value(f"lidar scan, {name}: numpy reference / compiled (medians)",
                           medians["numpy reference"] / medians["compiled"], "x", "same poses, same run")


def bench_node(bench: Benchmark, listeners: bool, samples: int = 8) -> None:
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("ROS_DOMAIN_ID", str(1 + os.getpid() % 100))
    import rclpy
    from nav_msgs.msg import Odometry
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import qos_profile_sensor_data
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import LaserScan
    from std_msgs.msg import Float64
    from tf2_msgs.msg import TFMessage

    from navsuite_testing.ros import spin_until, start_python, stop_process

    context = Context()
    rclpy.init(context=context)
    proc = start_python("sim2d.ros.cli", ["--rtf", "max"])
    node = Node("bench_sim2d", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    factors: list[float] = []
    node.create_subscription(Float64, "/sim2d/real_time_factor", lambda m: factors.append(m.data), 10)
    if listeners:
        heavy = ((LaserScan, "/scan"), (Odometry, "/odom"), (TFMessage, "/tf"), (Clock, "/clock"))
        for msg_type, topic in heavy:
            node.create_subscription(msg_type, topic, lambda m: None, qos_profile_sensor_data)
    try:
        spin_until(executor, lambda: len(factors) >= samples + 2, 120.0, "real-time factor reports")
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
        stop_process(proc)
    steady = factors[2:]   # the first reports include discovery and start-up
    label = "node real-time factor, max mode"
    if listeners:
        label += " (subscribers on scan, odom, tf, clock)"
    print(f"sim2d: {label}: samples {[round(f, 1) for f in steady]}")
    bench.record_value(label, statistics.median(steady), "x",
                       note=f"min {min(steady):.1f}, max {max(steady):.1f}, n={len(steady)}")


def main() -> None:
    parse_cli(__doc__)
    bench = Benchmark("sim2d")
    bench_core(bench)
    bench_large_world_lidar(bench)
    bench_node(bench, listeners=False)
    bench_node(bench, listeners=True)
    bench.save()


if __name__ == "__main__":
    main()
