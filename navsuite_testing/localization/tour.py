"""A scripted tour of turtlebot3_world in sim2d with the amcl node, scored against ground truth.

Shared by tests/integration/nav_stack/test_amcl_sim.py and bench/bench_localization.py. sim2d runs as
a child process (default drifting odometry), and so do map_server, amcl and
lifecycle_manager_localization (autostart), started from a Nav2-style parameter file exactly as a
deployment would; only the driver runs in this process. (With every node in one Python process the
/clock and /tf traffic at a real-time factor of 4 backlogs the executor by seconds.) The robot is
driven through TOUR by a small go-to-waypoint law on sim2d's ground truth (turn in place, then drive
with heading correction): the driver is test scaffolding, not the thing under test, and closing the
loop on ground truth keeps the robot in the free corridors whatever the timing jitter of a loaded
machine. Every amcl_pose is compared with the ground truth at its stamp. sim2d runs in lockstep with
amcl and the driver (both lockstep participants), as fast as they keep up unless ``rtf`` caps it.

The tour (map frame, m) runs between the pillar rows and columns (pillars r = 0.15 m at
x, y ∈ {-1.1, 0, 1.1}), never closer than 0.35 m to an obstacle edge: about 12 m in 70 s of sim time.
The simulator holds at t = 0 until the localization is active, so every run starts alike. A
kidnapped robot drives on, back and forth along the tour, until the filter has recovered (up to
RECOVERY_DRIVE s).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import UInt32
from std_srvs.srv import Empty, Trigger

from nav_stack.core.geometry import angle_diff
from nav_stack.ros.common.conversions import pose_from_2d
from nav_stack.ros.common.qos import LATCHED
from navsuite_testing.localization.nodes import MAP_YAML, call
from navsuite_testing.ros import connected, spin_until, start_python, stop_process
from ros_tools.geometry import yaw_of
from ros_tools.runtime.lockstep import LockstepParticipant

START = (-2.0, -0.5, 0.0)
TOUR = [(-1.65, -0.55), (1.65, -0.55), (1.65, 0.55), (0.55, 0.55), (0.55, 1.65), (-0.55, 1.65),
        (-0.55, -1.65)]
KIDNAP_AFTER = 1  # teleport when waypoint TOUR[1] is reached ...
KIDNAP_TO = (1.65, 1.45, -math.pi / 2)  # ... 2.0 m north of it, facing the next waypoint
DRIVER_ROLE = "tour_driver"  # lockstep role of the test's driver node
CONVERGED = 0.25  # m: position error below which (for good) localization counts as converged
TWIN_NOTE = """turtlebot3_world is point-symmetric about the origin except for its "head" block at
+x, whose face lies within 0.6 m of where the wall's corner would be: away from it, no scan tells a
pose from its 180° twin (-x, -y, yaw + pi), and a filter re-localizing after a kidnapping may
settle on either (seen: the twin held for over 100 s of driving)."""
RECOVERED_SAMPLES = 5  # converged amcl_poses after the kidnapping that count as a recovery
RECOVERY_DRIVE = 150.0  # sim s after the kidnapping the robot keeps driving while not recovered
RECOVERY = {"recovery_alpha_slow": 0.001, "recovery_alpha_fast": 0.1}  # Nav2's suggested values
MAX_V, MAX_W = 0.22, 1.0  # m/s, rad/s


@dataclass
class Sample:
    """One amcl_pose compared with the ground truth at its stamp."""

    t: float  # sim s
    distance: float  # m driven (ground truth) when it was taken
    error_xy: float  # m
    error_yaw: float  # rad
    error_twin: float  # m: position error against the truth's 180° twin (-x, -y; see TWIN_NOTE)


@dataclass
class TourResult:
    samples: list[Sample] = field(default_factory=list)
    collisions: int = 0
    kidnap_time: float | None = None
    finished: bool = False
    log: str = ""

    def converged_index(self, after: float = -math.inf, until: float = math.inf,
                        up_to_symmetry: bool = False) -> int | None:
        """First sample in (after, until) from which every error up to ``until`` stays below CONVERGED.

        ``up_to_symmetry``: the 180° twin of the true pose counts as converged too (TWIN_NOTE).
        """
        index = None
        for i, s in enumerate(self.samples):
            if s.t <= after or s.t >= until:
                continue
            if (min(s.error_xy, s.error_twin) if up_to_symmetry else s.error_xy) >= CONVERGED:
                index = None
            elif index is None:
                index = i
        return index

    def rms_after(self, index: int, until: float = math.inf) -> tuple[float, float]:
        """RMS position (m) and yaw (rad) errors over samples[index:] taken before ``until``."""
        chosen = [s for s in self.samples[index:] if s.t < until]
        xy = math.sqrt(float(np.mean([s.error_xy**2 for s in chosen])))
        yaw = math.sqrt(float(np.mean([s.error_yaw**2 for s in chosen])))
        return xy, yaw


class TourRun:
    """sim2d + map_server + amcl + a ground-truth driver; ``run()`` returns the scored TourResult."""

    def __init__(self, context: Any, *, rtf: float | str = "max", seed: int = 0,
                 global_localization: bool = False, kidnap: bool = False,
                 amcl_params: dict[str, Any] | None = None,
                 sim_args: tuple[str, ...] = ()) -> None:
        self.context, self.rtf, self.seed, self.sim_args = context, rtf, seed, sim_args
        self.global_localization, self.kidnap = global_localization, kidnap
        self.amcl_params: dict[str, Any] = dict(amcl_params or {})
        if not global_localization:  # the seed's initial pose, through Nav2's nested parameters
            self.amcl_params.update({"set_initial_pose": True, "initial_pose": {
                "x": START[0], "y": START[1], "yaw": START[2]}})
        self.result = TourResult()
        self._truth: list[tuple[float, float, float, float, float]] = []  # t, x, y, yaw, distance
        self._route = list(TOUR)  # grows by the tour backwards, then forwards... while a kidnap lasts
        self._waypoint = 0
        self._done = False
        self._started = False  # set once the localization is active; the driver then drives

    # -- callbacks -------------------------------------------------------------------------------
    def _on_truth(self, msg: Odometry) -> None:
        if not self._started:  # the localization is not active yet: the robot waits
            return
        p = msg.pose.pose.position
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        yaw = yaw_of(msg.pose.pose.orientation)
        distance = 0.0
        if self._truth:
            _, x0, y0, _, d0 = self._truth[-1]
            step = math.hypot(p.x - x0, p.y - y0)
            distance = d0 + (step if step < 0.3 else 0.0)  # a teleport is not driving
        if self._truth and t < self._truth[-1][0]:
            return
        self._truth.append((t, p.x, p.y, yaw, distance))
        self._drive(p.x, p.y, yaw)

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        t = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        stamps = [s[0] for s in self._truth]
        i = bisect.bisect_left(stamps, t)
        near = [j for j in (i - 1, i) if 0 <= j < len(stamps)]
        if not near:
            return
        j = min(near, key=lambda k: abs(stamps[k] - t))
        if abs(stamps[j] - t) > 0.05:
            return  # no ground truth at that time (e.g. a pose stamped before the first odometry)
        _, x, y, yaw, distance = self._truth[j]
        p = msg.pose.pose.position
        error_yaw = abs(angle_diff(yaw_of(msg.pose.pose.orientation), yaw))
        self.result.samples.append(Sample(t, distance, math.hypot(p.x - x, p.y - y), error_yaw,
                                          math.hypot(p.x + x, p.y + y)))

    def _drive(self, x: float, y: float, yaw: float) -> None:
        cmd = Twist()
        if self._waypoint >= len(self._route) and self._lost_after_kidnap():
            lap = TOUR if self._route[-1] == TOUR[0] else TOUR[::-1]
            self._route += lap[1:]  # back along the same corridors: no segment meets a pillar
        if self._waypoint >= len(self._route):
            self._done = True
        else:
            gx, gy = self._route[self._waypoint]
            dist = math.hypot(gx - x, gy - y)
            if dist < 0.05:
                if self.kidnap and self._waypoint == KIDNAP_AFTER and self.result.kidnap_time is None:
                    self._teleport()
                self._waypoint += 1
            else:
                heading = angle_diff(math.atan2(gy - y, gx - x), yaw)
                cmd.angular.z = max(-MAX_W, min(MAX_W, 2.0 * heading))
                if abs(heading) < 0.15:
                    cmd.linear.x = min(MAX_V, 0.8 * dist + 0.03)
        self.cmd_pub.publish(cmd)

    def _lost_after_kidnap(self) -> bool:
        """True while a kidnapped filter has not recovered and RECOVERY_DRIVE has not run out.

        Why: recovery by random particles is a matter of luck in a world as symmetric as this one
        (a filter can sit in a rotated copy of the true pose for tens of seconds). Driving on until
        it recovers makes the test measure whether it does, not whether the tour was long enough.
        """
        kidnapped = self.result.kidnap_time
        if kidnapped is None or self._truth[-1][0] > kidnapped + RECOVERY_DRIVE:
            return False
        after = self.result.converged_index(after=kidnapped, up_to_symmetry=True)
        return after is None or len(self.result.samples) - after < RECOVERED_SAMPLES

    def _teleport(self) -> None:
        msg = PoseStamped()
        msg.header.frame_id = "map"
        msg.pose = pose_from_2d(*KIDNAP_TO)
        self.teleport_pub.publish(msg)
        self.result.kidnap_time = self._truth[-1][0]

    # -- run ---------------------------------------------------------------------------------------
    def _params_file(self, directory: Path) -> Path:
        path = directory / "localization_params.yaml"
        doc = {
            "map_server": {"ros__parameters": {"yaml_filename": str(MAP_YAML)}},
            "amcl": {"ros__parameters": {"use_sim_time": True, **self.amcl_params}},
            "lifecycle_manager_localization": {"ros__parameters": {
                "node_names": ["map_server", "amcl"], "autostart": True}},
        }
        path.write_text(yaml.safe_dump(doc))
        return path

    def run(self, directory: Path, timeout: float = 240.0) -> TourResult:
        """Drive the tour; sim2d, map_server, amcl and their lifecycle manager run as child processes."""
        params = str(self._params_file(directory))
        procs = {
            "sim2d": start_python("sim2d.ros.cli", [
                "--world", "turtlebot3_world", "--robot", "waffle", "--rtf", str(self.rtf), "--seed",
                str(self.seed), "--x", str(START[0]), "--y", str(START[1]), "--yaw", str(START[2]),
                "--lockstep-participants", f"amcl,{DRIVER_ROLE}", *self.sim_args]),
            "map_server": start_python("nav_stack.ros.localization.map_server",
                                       ["--ros-args", "--params-file", params]),
            "amcl": start_python("nav_stack.ros.localization.amcl_node",
                                 ["--ros-args", "--params-file", params]),
            "manager": start_python("nav_stack.ros.lifecycle.lifecycle_manager", [
                "--ros-args", "-r", "__node:=lifecycle_manager_localization", "--params-file", params]),
        }
        probe = Node("tour_driver", context=self.context)
        executor = SingleThreadedExecutor(context=self.context)
        executor.add_node(probe)
        self.cmd_pub = probe.create_publisher(Twist, "/cmd_vel", 10)
        self.teleport_pub = probe.create_publisher(PoseStamped, "/sim2d/teleport", 10)
        endpoints = [
            self.cmd_pub, *([self.teleport_pub] if self.kidnap else []),
            probe.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", self._on_pose, LATCHED),
            probe.create_subscription(Odometry, "/ground_truth", self._on_truth, 10),
        ]
        counts: list[int] = []

        def on_collision_count(msg: UInt32) -> None:
            counts.append(msg.data)

        probe.create_subscription(UInt32, "/sim2d/collision_count", on_collision_count, LATCHED)
        # The sim holds at t = 0 for the driver (and AMCL) until the driver is connected and the
        # localization is active: no amcl_pose or ground truth is missed while DDS discovery is still
        # matching them, and the tour starts at the same sim time however long the startup took.
        is_connected = connected(endpoints)
        lockstep = LockstepParticipant(probe, DRIVER_ROLE, ready=lambda: self._started and is_connected())

        def crashed() -> bool:
            return any(proc.poll() is not None for proc in procs.values())

        try:
            is_active = probe.create_client(Trigger, "/lifecycle_manager_localization/is_active")
            spin_until(executor, lambda: crashed() or call(executor, is_active, Trigger.Request()).success,
                       60.0, "lifecycle_manager_localization to report active", step=0.2)
            assert not crashed(), "a child process exited during startup"
            if self.global_localization:
                reinitialize = probe.create_client(Empty, "/reinitialize_global_localization")
                call(executor, reinitialize, Empty.Request())
            self._started = True
            spin_until(executor, lambda: self._done or crashed(), timeout, "the end of the tour")
            self.cmd_pub.publish(Twist())
            spin_until(executor, lambda: bool(counts), 10.0, "sim2d/collision_count")
            self.result.collisions = counts[-1]
            self.result.finished = self._done
        finally:
            lockstep.destroy()
            executor.shutdown()
            probe.destroy_node()
            self.result.log = "".join(f"--- {name}\n{stop_process(proc)}" for name, proc in procs.items())
        return self.result
