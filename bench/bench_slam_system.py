"""SLAM on the ROS graph: time per processed scan inside the slam node, and a whole exploration run.

1. Node timing: the slam node in this process, fed by the fake robot of
   navsuite_testing/slam/fakes.py (analytic hexagon room, 360 beams), waiting for each scan's
   slam/pose; the node records the wall time of every processed scan (``SlamNode.process_times``).
2. Exploration: sim2d (``--rtf``, default 1: what the stack sustains on 2 cores; drifting odometry)
   + the ``nav-bringup --slam`` processes + the Nav2 servers, and ``nav-explore -f`` from the seeds'
   spawn until complete (navsuite_testing/slam/stack.py).
   Recorded: occupied-cell IoU with the observable walls of maps/turtlebot3_world.yaml (one-cell
   tolerance), SLAM pose error against ground truth (median and max), goals, duration (sim s, wall s).

Run: ``.venv/bin/python -m bench.bench_slam_system [--rtf 1] [--node-only] [--no-record]``
(``--node-only`` skips the exploration run, ``--no-record`` only prints).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
os.environ.setdefault("ROS_DOMAIN_ID", str(1 + os.getpid() % 100))

import rclpy
from rclpy.context import Context
from rclpy.parameter import Parameter

from bench.harness import Benchmark, Stats
from nav_stack.ros.slam.slam_bringup import slam_processes
from nav_stack.ros.slam.slam_node import SlamNode
from navsuite_testing.nav.world import Harness
from navsuite_testing.ros import release_dds_participants
from navsuite_testing.slam.fakes import START, FakeRobot, tour
from navsuite_testing.slam.node_probe import Probe as NodeProbe
from navsuite_testing.slam.node_probe import drive
from navsuite_testing.slam.stack import (
    PARAMS_FILE,
    Stack,
    compare_with_reference,
    explore,
    nav_specs,
    progress_numbers,
    sim_spec,
)
from navsuite_testing.slam.system_probe import Probe as SystemProbe


def node_timing(bench: Benchmark) -> None:
    context = Context()
    rclpy.init(context=context)
    harness = Harness(context)
    try:
        slam = SlamNode(context=context, parameter_overrides=[Parameter("map_start_pose", value=list(START))])
        robot, probe = FakeRobot(context=context), NodeProbe(context=context)
        harness.add(slam, robot, probe)
        harness.bring_up(slam)
        drive(robot, probe, tour(robot.world), slam)
        stats = Stats.of(slam.process_times)
        bench.record("node: SLAM time per processed scan (360 beams, worker thread)", stats, "ms", 1e3,
                     note=f"hexagon room tour, {stats.count} scans processed")
    finally:
        harness.close()
        rclpy.shutdown(context=context)
        release_dds_participants()  # the exploration's processes must find each other (see its doc)


def exploration(bench: Benchmark, rtf: float) -> None:
    context = Context()
    rclpy.init(context=context)
    probe = SystemProbe(context)
    directory = Path(tempfile.mkdtemp(prefix="bench_slam_"))
    stack = Stack([sim_spec(rtf), *slam_processes(PARAMS_FILE), *nav_specs()])
    try:
        started = time.monotonic()
        done = explore(directory / "explored", max_time=900.0, timeout=1500.0)
        wall = time.monotonic() - started
        if done.returncode != 0:
            print(done.stdout[-3000:], done.stderr[-3000:], stack.tail(), file=sys.stderr)
            raise SystemExit(f"nav-explore failed with exit code {done.returncode}")
        numbers = progress_numbers(done.stdout)
        iou = compare_with_reference(directory / "explored.yaml")
        errors = Stats.of(probe.errors)
        note = (f"RTF {rtf:g}, {numbers['goals']:.0f} goals ({numbers['failed']:.0f} failed), "
                f"{numbers['mapped']:.1f} m2")
        bench.record_value("exploration: occupied IoU vs observable reference walls (1-cell tol.)", iou, "",
                           note=note)
        bench.record("exploration: SLAM pose error vs ground truth", errors, "m", note=note)
        bench.record_value("exploration: duration (sim)", numbers["sim_s"], "s", note=note)
        bench.record_value("exploration: duration (wall)", wall, "s", note=note)
    finally:
        stack.close()
        probe.close()
        rclpy.shutdown(context=context)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rtf", type=float, default=1.0, help="real-time factor of the exploration run")
    parser.add_argument("--node-only", action="store_true", help="skip the exploration run")
    parser.add_argument("--no-record", action="store_true", help="print, do not append to RESULTS.md")
    args = parser.parse_args()
    bench = Benchmark("slam_system")
    node_timing(bench)
    if not args.node_only:
        exploration(bench, args.rtf)
    if not args.no_record:
        bench.save()


if __name__ == "__main__":
    main()
