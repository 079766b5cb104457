"""A short sim2d run recorded with ``navsuite-bag record`` (replayed by tests/helpers/bag_replay.py).

sim2d runs as a child process at a real-time factor of 5; a Twist publisher (its own rclpy
context, spun in a background thread) drives the robot in an arc while the recorder CLI records
every topic for a few seconds of sim time. The recorder starts only once the ground truth shows
the robot moving: its window is under a second of wall time, and on a loaded machine the driver's
first commands used to reach sim2d after it had closed (a recording of a robot standing still).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import rclpy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navsuite_testing.ros import BackgroundSpin, start_python, stop_process, wait_until
from tests.helpers.bag_replay import BAG_CLI

#: Sim seconds to record; with --rtf 5 that is under a second of wall time.
RECORD_SECONDS = 3.0
#: Wall-clock bounds for a loaded 2-core machine; a passing run is much faster.
STARTUP_TIMEOUT = 30.0
PROCESS_TIMEOUT = 45.0


@dataclass
class Recording:
    """The recorded file and the recorder's output (for failure messages)."""

    path: Path
    output: str


@contextmanager
def _driver(context: Context) -> Iterator[Node]:
    """A node publishing an arc-shaped Twist on /cmd_vel at 20 Hz (wall), spun in a thread."""
    node = Node("bag_test_driver", context=context)
    publisher = node.create_publisher(Twist, "/cmd_vel", 10)
    command = Twist()
    command.linear.x, command.angular.z = 0.2, 0.5
    node.create_timer(0.05, lambda: publisher.publish(command))
    node.moved = 0.0  # type: ignore[attr-defined]  # m from the first ground-truth pose
    first: list[tuple[float, float]] = []

    def on_truth(msg: Odometry) -> None:
        p = msg.pose.pose.position
        if not first:
            first.append((p.x, p.y))
        node.moved = math.hypot(p.x - first[0][0], p.y - first[0][1])  # type: ignore[attr-defined]

    node.create_subscription(Odometry, "ground_truth", on_truth, 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    spin = BackgroundSpin(executor, "arc driver")
    try:
        yield node
    finally:
        spin.stop(node)


def record_sim(out: Path) -> Recording:
    """Run sim2d, drive it, record all topics for RECORD_SECONDS of sim time into ``out``."""
    sim = start_python("sim2d.ros.cli", ["--rtf", "5"])
    recorder = None
    context = Context()
    rclpy.init(context=context)
    try:
        with _driver(context) as driver:
            wait_until(lambda: driver.moved > 0.02, STARTUP_TIMEOUT, "the robot to move")  # type: ignore[attr-defined]
            recorder = start_python(BAG_CLI, [
                "record", "-a", "-x", "^/(rosout|parameter_events)$", "-o", str(out),
                "--use-sim-time", "--max-duration", str(RECORD_SECONDS),
            ])
            wait_until(lambda: recorder.poll() is not None, STARTUP_TIMEOUT + PROCESS_TIMEOUT,
                       "the recorder to finish")
    finally:
        output = stop_process(recorder) if recorder is not None else ""
        rclpy.shutdown(context=context)
        stop_process(sim)
    assert recorder.returncode == 0, output
    return Recording(out, output)
