"""A fleet through the whole stack (issue 48): N robots x K random goals each in depot_large, at once.

``nav-bringup --robots N --world depot_large`` runs the fleet (one simulator, one namespaced Nav2 stack
per robot, lockstep at ``--rtf max``); this client drives every robot at the same time, each through its
own ``/robotN/navigate_to_pose``, one goal after the other. A goal is a free map cell with at least
MIN_CLEARANCE (0.4 m) to any occupied or unknown cell, at least MIN_TRAVEL from the robot, at least
GOAL_SPACING from every other robot and every other robot's goal (two robots sent to one spot would
measure a queue, not navigation), and that robot's planner reaches it (``/robotN/compute_path_to_pose``
from where it stands). Seeded (``--seed``); which goal each robot gets still depends on timing.

Recorded: goals reached (%), collisions split into robot-robot and robot-wall (sim2d's
``/robotN/sim2d/collisions`` per new contact; a contact is robot-robot when another robot's centre is
within the two robots' circumradii plus CONTACT_SLACK at that moment, and sim2d reports it on both
robots, so two such events are one collision), and the real-time factor the fleet sustained: the
median over RTF_WINDOW s (wall) windows of /clock's advance, and the whole run's sim over wall time.
Targets (issue 48): >= 98 % of goals, 0 robot-robot and 0 robot-wall collisions, sustained RTF >= 2.

    .venv/bin/python -m bench.bench_fleet_nav [--robots 3] [--goals 20] [--world depot_large]
                                              [--robot tb4] [--params FILE] [--seed 7] [--note TEXT]
                                              [--no-record]
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import statistics
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note
from bench.nav_driver import Driver
from bench.nav_session import MIN_CLEARANCE, READY_TIMEOUT, STOP_TIMEOUT, _watch, free_poses, map_yaml

REPO = Path(__file__).resolve().parents[1]
MIN_TRAVEL = 1.0  # m between a robot and its next goal
GOAL_SPACING = 1.5  # m between a goal and every other robot and its goal
CONTACT_SLACK = 0.15  # m beyond two circumradii within which a contact counts as robot-robot
GOAL_TIMEOUT = 300.0  # s (wall) per goal
RTF_WINDOW = 10.0  # s (wall)
DRAWS = 2000  # goal candidates a robot may draw before the run gives up


@dataclass
class Robot:
    """One robot's client side: its action clients, its truth, its goals and its contacts."""

    name: str
    radius: float  # m, the model's circumradius
    nav: Any
    plan: Any
    truth: tuple[float, float] | None = None
    goal: tuple[float, float] | None = None
    reached: int = 0
    failed: list[str] = field(default_factory=list)
    robot_contacts: int = 0
    wall_contacts: int = 0

    def on_truth(self, msg: Any) -> None:
        self.truth = (msg.pose.pose.position.x, msg.pose.pose.position.y)


class FleetClient:
    """One node for the whole fleet, spun in a background thread (a SingleThreadedExecutor, as
    bench.nav_driver says why)."""

    def __init__(self, members: list[tuple[str, str]]) -> None:
        import rclpy
        from geometry_msgs.msg import PointStamped
        from nav2_msgs.action import ComputePathToPose, NavigateToPose
        from nav_msgs.msg import Odometry
        from rosgraph_msgs.msg import Clock

        from ros_tools.runtime.actions import ActionClient
        from ros_tools.runtime.executor import make_executor
        from sim2d.core.robot import ROBOTS

        rclpy.init()
        self.node = rclpy.create_node("bench_fleet_nav")
        self.sim_time = 0.0
        self.lock = threading.Lock()  # held while a robot picks its goal
        self.robots = {
            name: Robot(name, ROBOTS[model].bounding_radius(),
                        ActionClient(self.node, NavigateToPose, f"/{name}/navigate_to_pose"),
                        ActionClient(self.node, ComputePathToPose, f"/{name}/compute_path_to_pose"))
            for name, model in members}
        for robot in self.robots.values():
            self.node.create_subscription(Odometry, f"/{robot.name}/ground_truth", robot.on_truth, 10)
            self.node.create_subscription(PointStamped, f"/{robot.name}/sim2d/collisions",
                                          self._contact_of(robot), 10)
        self.node.create_subscription(Clock, "/clock", self._on_clock, 10)
        self.executor = make_executor("single")
        self.executor.add_node(self.node)
        self._closing = threading.Event()
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        while not self._closing.is_set():
            self.executor.spin_once(timeout_sec=0.1)

    def _on_clock(self, msg: Any) -> None:
        self.sim_time = msg.clock.sec + msg.clock.nanosec * 1e-9

    def _contact_of(self, robot: Robot) -> Any:
        """The /<robot>/sim2d/collisions callback: count the new contact as robot-robot or robot-wall."""
        def on_contact(_msg: Any) -> None:
            near = [other for other in self.robots.values() if other is not robot and other.truth
                    and robot.truth
                    and math.dist(other.truth, robot.truth) <= robot.radius + other.radius + CONTACT_SLACK]
            if near:
                robot.robot_contacts += 1
            else:
                robot.wall_contacts += 1
        return on_contact

    def ready(self) -> bool:
        return self.sim_time > 0.0 and all(r.nav.server_is_ready() and r.plan.server_is_ready() and r.truth
                                           for r in self.robots.values())

    def close(self) -> None:
        import rclpy

        self._closing.set()   # stopped and joined first: a shutdown under a spinning thread raises there
        self._thread.join(timeout=5.0)
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown()


def _plannable(robot: Robot, goal: tuple[float, float]) -> bool:
    from nav2_msgs.action import ComputePathToPose

    sent = robot.plan.send_goal_async(ComputePathToPose.Goal(goal=Driver.pose(*goal), use_start=False))
    if not Driver._wait(sent, 30.0) or not sent.result().accepted:
        return False
    result = sent.result().get_result_async()
    return Driver._wait(result, 30.0) and result.result().result.error_code == 0


def _draw_goal(client: FleetClient, robot: Robot, candidates: np.ndarray,
               rng: np.random.Generator) -> tuple[float, float]:
    for _ in range(DRAWS):
        with client.lock:  # one robot picks at a time, so two never pick the same spot
            x, y = (float(v) for v in candidates[rng.integers(len(candidates))])
            others = [p for r in client.robots.values() if r is not robot for p in (r.truth, r.goal) if p]
            if robot.truth is None or math.dist(robot.truth, (x, y)) < MIN_TRAVEL \
                    or any(math.dist(p, (x, y)) < GOAL_SPACING for p in others):
                continue
            robot.goal = (x, y)
        if _plannable(robot, (x, y)):
            return x, y
        robot.goal = None
    raise RuntimeError(f"{robot.name}: no plannable goal in {DRAWS} candidates")


def _drive(client: FleetClient, robot: Robot, goals: int, candidates: np.ndarray, seed: int,
           stop: threading.Event) -> None:
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import NavigateToPose

    rng = np.random.default_rng(seed)
    for index in range(goals):
        if stop.is_set():
            return
        x, y = _draw_goal(client, robot, candidates, rng)
        yaw = float(rng.uniform(-math.pi, math.pi))
        started = client.sim_time
        sent = robot.nav.send_goal_async(NavigateToPose.Goal(pose=Driver.pose(x, y, yaw)))
        if not Driver._wait(sent, 30.0) or not sent.result().accepted:
            robot.failed.append(f"goal {index + 1} not accepted")
            continue
        result = sent.result().get_result_async()
        if not Driver._wait(result, GOAL_TIMEOUT):
            sent.result().cancel_goal_async()
            robot.failed.append(f"goal {index + 1} ({x:.2f}, {y:.2f}): no result in {GOAL_TIMEOUT:.0f} s "
                                "wall")
            continue
        response = result.result()
        ok = response.status == GoalStatus.STATUS_SUCCEEDED
        robot.reached += ok
        if not ok:
            robot.failed.append(f"goal {index + 1} ({x:.2f}, {y:.2f}): {response.result.error_code} "
                                f"{response.result.error_msg}")
        print(f"{robot.name} goal {index + 1:2d}/{goals} ({x:6.2f}, {y:5.2f}): {'ok ' if ok else 'FAIL'} "
              f"{client.sim_time - started:5.1f} s sim", flush=True)
    robot.goal = None


def _rtf_windows(samples: list[tuple[float, float]]) -> list[float]:
    """Sim s per wall s over consecutive RTF_WINDOW s windows of (wall s, sim s) samples."""
    rates, start = [], samples[0] if samples else None
    for wall, sim in samples[1:]:
        if start is not None and wall - start[0] >= RTF_WINDOW:
            rates.append((sim - start[1]) / (wall - start[0]))
            start = (wall, sim)
    return rates


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robots", type=int, default=3)
    parser.add_argument("--goals", type=int, default=20, help="goals per robot")
    parser.add_argument("--world", default="depot_large")
    parser.add_argument("--robot", default="tb4",
                        help="the robots' model (default tb4: the waffle's 3.5 m lidar sees too few walls "
                             "in depot_large's hall for the controller's localization guard; bench_soak "
                             "uses the tb4 there too)")
    parser.add_argument("--params", type=Path, default=None,
                        help="nav-bringup --params (default: the robot's)")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--note", default="")
    parser.add_argument("--no-record", action="store_true")
    return parser


def _start_fleet(args: argparse.Namespace) -> subprocess.Popen[str]:
    command = [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup", "--robots", str(args.robots),
               "--world", args.world, "--robot", args.robot, "--rtf", "max",
               "--log-dir", str(REPO / "artifacts" / "logs" / "bench_fleet_nav"),
               *(["--params", str(args.params)] if args.params else [])]
    process = subprocess.Popen(command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    ready = threading.Event()
    threading.Thread(target=_watch, args=(process, ready), daemon=True).start()
    if not ready.wait(READY_TIMEOUT):
        _stop_fleet(process)
        raise RuntimeError(f"nav-bringup did not print 'Nav2 is ready' within {READY_TIMEOUT:.0f} s")
    return process


def _stop_fleet(process: subprocess.Popen[str]) -> None:
    process.send_signal(signal.SIGINT)
    try:
        process.wait(timeout=STOP_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def main() -> int:
    from nav_stack.ros.bringup.nav_bringup import parse_args

    args = _parser().parse_args()
    domain = enter_local_domain()
    version = code_version_with_fingerprint()
    print(f"fleet_nav: ROS_DOMAIN_ID {domain}, code {version}", flush=True)
    plan = parse_args(["--robots", str(args.robots), "--world", args.world, "--robot", args.robot])
    members = [(m.name, m.model) for m in plan.members]
    candidates = free_poses(map_yaml(args.world), MIN_CLEARANCE)
    load = os.getloadavg()[0]
    process = _start_fleet(args)
    client = FleetClient(members)
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())   # Ctrl-C: finish the current goals, record
    try:
        deadline = time.monotonic() + 60.0
        while not client.ready():
            if time.monotonic() > deadline:
                raise RuntimeError("the robots' navigate_to_pose / compute_path_to_pose, truth or /clock "
                                   "are missing")
            time.sleep(0.1)
        drivers = [threading.Thread(target=_drive,
                                    args=(client, robot, args.goals, candidates, args.seed + i, stop))
                   for i, robot in enumerate(client.robots.values())]
        samples = [(time.monotonic(), client.sim_time)]
        for driver in drivers:
            driver.start()
        while any(driver.is_alive() for driver in drivers):
            time.sleep(1.0)
            samples.append((time.monotonic(), client.sim_time))
        robots = list(client.robots.values())
    finally:
        client.close()
        _stop_fleet(process)
    total = args.robots * args.goals
    reached = sum(r.reached for r in robots)
    wall, sim = samples[-1][0] - samples[0][0], samples[-1][1] - samples[0][1]
    windows = _rtf_windows(samples)
    note = (f"{args.robots} x {args.goals} goals, {args.world}/{args.robot}, seed {args.seed}, "
            f"lockstep rtf max, load {load:.1f} at start, {version_note(version)}"
            + (f"; {args.note}" if args.note else ""))
    bench = Benchmark("fleet_navigation")
    bench.record_value("fleet goals reached", 100.0 * reached / max(total, 1), "%", note)
    bench.record_value("fleet robot-robot collisions", math.ceil(sum(r.robot_contacts for r in robots) / 2),
                       "count", f"{note}; a contact is reported on both robots")
    bench.record_value("fleet robot-wall collisions", float(sum(r.wall_contacts for r in robots)), "count",
                       note)
    if windows:
        bench.record_value("fleet sustained real-time factor (median)", statistics.median(windows), "x",
                           f"{note}; {len(windows)} windows of {RTF_WINDOW:.0f} s wall, "
                           f"lowest {min(windows):.2f}")
    bench.record_value("fleet real-time factor (whole run)", sim / max(wall, 1e-9), "x",
                       f"{note}; {sim:.0f} sim s in {wall:.0f} wall s")
    for robot in robots:
        for failure in robot.failed:
            print(f"{robot.name}: {failure}", flush=True)
    if not args.no_record:
        bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
