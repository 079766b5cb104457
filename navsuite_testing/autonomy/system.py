"""Whole-stack helpers for the patrol system tests and bench: start ``nav-bringup``, set AMCL's
initial pose (the TurtleBot3 spawn pose), run ``nav-autonomy`` and read its result lines."""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass

from ros_tools.launch import Launcher, ProcessSpec

READY = r"Nav2 is ready"
SPAWN = (-2.0, -0.5, 0.0)
CYCLE_LINE = re.compile(r"cycle (\d+): root (SUCCESS|FAILURE).* in ([0-9.]+) s")
VISITED_LINE = re.compile(r"finished \d+ cycles; visited: (.*)$")


def stack_available() -> bool:
    """True when the real stack (nav_stack.ros.bringup.nav_bringup) exists."""
    return importlib.util.find_spec("nav_stack.ros.bringup.nav_bringup") is not None


def bringup_command(rtf: str, extra: Sequence[str] = ()) -> list[str]:
    exe = shutil.which("nav-bringup")
    base = [exe] if exe else [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup"]
    return [*base, "--rtf", rtf, *extra]


class RecordingLauncher(Launcher):
    """A Launcher that keeps every console line in ``lines``, so a test can check the stack's warnings."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        super().__init__(output=self.lines.append)


def start_stack(rtf: str, extra: Sequence[str] = (), ready_timeout: float = 240.0) -> RecordingLauncher:
    """A launcher running nav-bringup, returned once it printed "Nav2 is ready"."""
    launcher = RecordingLauncher()
    command = bringup_command(rtf, extra)
    launcher.start([ProcessSpec("nav", command, ready=READY, ready_timeout=ready_timeout)])
    return launcher


def set_initial_pose(timeout: float = 60.0) -> None:
    """Publish /initialpose at the spawn pose until /amcl_pose answers near it."""
    import math

    import rclpy
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    context = Context()
    rclpy.init(context=context)
    node = Node("patrol_initial_pose", context=context,
                parameter_overrides=[Parameter("use_sim_time", value=True)])
    got: list[tuple[float, float]] = []
    qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def on_amcl_pose(msg: PoseWithCovarianceStamped) -> None:
        got.append((msg.pose.pose.position.x, msg.pose.pose.position.y))

    node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", on_amcl_pose, qos)
    pub = node.create_publisher(PoseWithCovarianceStamped, "/initialpose", 10)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    try:
        deadline, next_pub = time.monotonic() + timeout, 0.0
        while not (got and math.hypot(got[-1][0] - SPAWN[0], got[-1][1] - SPAWN[1]) < 0.3):
            if time.monotonic() > deadline:
                raise AssertionError(f"AMCL did not report the spawn pose within {timeout} s "
                                     f"(got {got[-1:]})")
            if time.monotonic() > next_pub:
                msg = PoseWithCovarianceStamped()
                msg.header.frame_id = "map"
                msg.pose.pose.position.x, msg.pose.pose.position.y = SPAWN[0], SPAWN[1]
                msg.pose.pose.orientation.w = 1.0
                msg.pose.covariance[0] = msg.pose.covariance[7] = 0.25
                msg.pose.covariance[35] = 0.06853891945200942
                pub.publish(msg)
                next_pub = time.monotonic() + 2.0
            executor.spin_once(timeout_sec=0.05)
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)


@dataclass
class AutonomyRun:
    returncode: int
    output: str
    wall_s: float

    def cycles(self) -> list[tuple[str, float]]:
        """(root result, sim s) per cycle, from the node's log."""
        return [(m.group(2), float(m.group(3))) for m in CYCLE_LINE.finditer(self.output)]

    def visited(self) -> list[str]:
        for line in self.output.splitlines():
            match = VISITED_LINE.search(line)
            if match:
                return [item.strip() for item in match.group(1).split(",")]
        return []


def run_autonomy(params: dict[str, object], timeout: float) -> AutonomyRun:
    """Run ``python -m nav_stack.ros.autonomy.node`` with ``params`` (and use_sim_time) to its exit."""
    from navsuite_testing.ros import start_python

    args = ["--ros-args", "-p", "use_sim_time:=true"]
    for name, value in params.items():
        args += ["-p", f"{name}:={value}"]
    started = time.monotonic()
    proc = start_python("nav_stack.ros.autonomy.node", args)
    try:
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate()
        return AutonomyRun(-1, out, time.monotonic() - started)
    finally:  # never leave the node running: it would send goals to the next test's stack
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return AutonomyRun(proc.returncode, out, time.monotonic() - started)
