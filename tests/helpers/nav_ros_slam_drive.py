"""The slam node mapping turtlebot3_world in sim2d while a scripted driver moves the robot.

Shared by tests/integration/nav_stack/test_slam_node_sim.py and bench/bench_slam_system.py. sim2d
(default drifting odometry) and the slam node (``--autostart``, the project's ``slam`` parameters)
run as child processes, as a deployment would; only the driver and the probe run in this process.
The driver closes a go-to-waypoint loop on sim2d's ground truth over TOUR (the collision-free route
between the pillars of navsuite_testing/localization/tour.py): it is scaffolding, not the thing under test.
Every ``slam/pose`` is compared with the ground truth at its stamp; every /map is kept.
"""

from __future__ import annotations

import bisect
import math
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import UInt32

from nav_stack.ros.common.qos import LATCHED
from navsuite_testing.localization.tour import MAX_V, MAX_W, START, TOUR
from navsuite_testing.ros import REPO, connected, spin_until, start_python, stop_process
from ros_tools.runtime.lockstep import LockstepParticipant

PARAMS_FILE = REPO / "config" / "nav2_params.yaml"
#: m: what the slam node's pose error (slam/pose against ground truth) must stay within on a
#: turtlebot3_world drive. Twelve tour runs in lockstep (2026-11-25): median 0.019-0.058 in two
#: clusters near 0.02 and 0.05, max 0.047-0.163; one CI run reached 0.107. The upper cluster was the
#: robot already moving when slam took its first scan; since the driver waits for the first map,
#: three runs gave medians 0.022-0.024 and max 0.050-0.058. Exploration runs reached 0.123. The
#: bounds sit above that spread and far below the drifting odometry's tens of centimetres.
SLAM_MAX_MEDIAN_ERROR = 0.08
SLAM_MAX_ERROR = 0.2
DRIVER_ROLE = "slam_drive_probe"  # lockstep role of the test's driver node


@dataclass
class DriveResult:
    """Pose errors (m) of slam/pose against ground truth, the maps received, and the collision count."""

    errors: list[tuple[float, float]] = field(default_factory=list)  # (sim s, m)
    maps: list[OccupancyGrid] = field(default_factory=list)
    collisions: int = -1
    finished: bool = False
    log: str = ""


def slam_params_file(directory: Path, **overrides: Any) -> Path:
    """The ``slam`` section of config/nav2_params.yaml with use_sim_time and ``overrides``."""
    doc = yaml.safe_load(PARAMS_FILE.read_text())
    params = {**doc["slam"]["ros__parameters"], "use_sim_time": True, **overrides}
    path = directory / "slam_params.yaml"
    path.write_text(yaml.safe_dump({"slam": {"ros__parameters": params}}))
    return path


def start_slam(params: Path) -> subprocess.Popen[str]:
    args = ["--autostart", "--ros-args", "--params-file", str(params)]
    return start_python("nav_stack.ros.slam.slam_node", args)


def start_sim(rtf: float | str, seed: int = 0) -> subprocess.Popen[str]:
    """sim2d in lockstep with the slam node and the driver (DRIVER_ROLE)."""
    return start_python("sim2d.ros.cli", [
        "--world", "turtlebot3_world", "--robot", "waffle", "--rtf", str(rtf), "--seed", str(seed),
        "--x", str(START[0]), "--y", str(START[1]), "--yaw", str(START[2]),
        "--lockstep-participants", f"slam,{DRIVER_ROLE}"])


class SlamDrive:
    """sim2d + slam + a ground-truth driver over ``waypoints``; ``run()`` fills a DriveResult.

    After ``run`` the child processes and the probe node stay up (for service calls) until ``close``.
    """

    def __init__(self, context: Any, directory: Path, *, rtf: float | str = "max", seed: int = 0,
                 waypoints: list[tuple[float, float]] | None = None) -> None:
        self.waypoints = list(TOUR if waypoints is None else waypoints)
        self.result = DriveResult()
        self._truth: list[tuple[float, float, float]] = []  # t, x, y
        self.pose: tuple[float, float, float] | None = None  # latest ground truth x, y, yaw (m, rad)
        self._index = 0
        self.procs = {"sim2d": start_sim(rtf, seed), "slam": start_slam(slam_params_file(directory))}
        self.probe = Node("slam_drive_probe", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.probe)
        self.cmd_pub = self.probe.create_publisher(Twist, "/cmd_vel", 10)
        endpoints = [
            self.cmd_pub,
            self.probe.create_subscription(PoseWithCovarianceStamped, "/slam/pose", self._on_pose, LATCHED),
            self.probe.create_subscription(OccupancyGrid, "/map", self.result.maps.append, LATCHED),
            self.probe.create_subscription(Odometry, "/ground_truth", self._on_truth, 10),
        ]
        self._counts: list[int] = []
        self.probe.create_subscription(UInt32, "/sim2d/collision_count",
                                       lambda m: self._counts.append(m.data), LATCHED)
        # The sim holds until the driver is connected to sim2d and slam: the first maps are then seen.
        self.lockstep = LockstepParticipant(self.probe, DRIVER_ROLE, ready=connected(endpoints))

    def crashed(self) -> bool:
        return any(proc.poll() is not None for proc in self.procs.values())

    def _on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        if self._truth and t <= self._truth[-1][0]:
            return
        self._truth.append((t, p.x, p.y))
        self.pose = (p.x, p.y, 2.0 * math.atan2(q.z, q.w))
        self._drive(*self.pose)

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        stamps = [s[0] for s in self._truth]
        i = bisect.bisect_left(stamps, t)
        near = [j for j in (i - 1, i) if 0 <= j < len(stamps)]
        if not near:
            return
        j = min(near, key=lambda k: abs(stamps[k] - t))
        if abs(stamps[j] - t) > 0.05:
            return
        p = msg.pose.pose.position
        self.result.errors.append((t, math.hypot(p.x - self._truth[j][1], p.y - self._truth[j][2])))

    def _drive(self, x: float, y: float, yaw: float) -> None:
        cmd = Twist()
        # Stand still until slam has mapped: it anchors the map at map_start_pose with its first scan,
        # so a robot already moving then leaves the whole run offset (CI run Y: median error 0.107 m
        # against 0.05 m usually).
        if self.result.maps and self._index < len(self.waypoints):
            gx, gy = self.waypoints[self._index]
            dist = math.hypot(gx - x, gy - y)
            if dist < 0.05:
                self._index += 1
            else:
                heading = math.atan2(math.sin(math.atan2(gy - y, gx - x) - yaw),
                                     math.cos(math.atan2(gy - y, gx - x) - yaw))
                cmd.angular.z = max(-MAX_W, min(MAX_W, 2.0 * heading))
                if abs(heading) < 0.15:
                    cmd.linear.x = min(MAX_V, 0.8 * dist + 0.03)
        self.cmd_pub.publish(cmd)

    @property
    def sim_time(self) -> float:
        """Stamp (sim s) of the newest ground truth heard; -inf before the first."""
        return self._truth[-1][0] if self._truth else -math.inf

    @property
    def done(self) -> bool:
        return self._index >= len(self.waypoints)

    def run(self, timeout: float = 240.0) -> DriveResult:
        """Wait for the first map, drive every waypoint, then read the collision count."""
        spin_until(self.executor, lambda: bool(self.result.maps) or self.crashed(), 60.0, "the first /map")
        assert not self.crashed(), "a child process exited during startup"
        spin_until(self.executor, lambda: self.done or self.crashed(), timeout, "the end of the drive")
        self.cmd_pub.publish(Twist())
        spin_until(self.executor, lambda: bool(self._counts), 10.0, "sim2d/collision_count")
        self.result.collisions = self._counts[-1]
        self.result.finished = self.done and not self.crashed()
        return self.result

    def close(self) -> None:
        self.lockstep.destroy()
        self.executor.shutdown()
        self.probe.destroy_node()
        self.result.log = "".join(f"--- {name}\n{stop_process(proc)}" for name, proc in self.procs.items())
