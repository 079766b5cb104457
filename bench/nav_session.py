"""One whole-stack session of random goals: start nav-bringup, drive goals through it, stop it.

Shared by bench_navigation (one world) and bench_soak (several worlds and robots, one stack each).

Goals are sampled (seeded) among free map cells with >= ``MIN_CLEARANCE`` to any occupied or
unknown cell, each one reachable per the running planner (compute_path_to_pose from the previous
goal; the plan's length is the optimal path). The ideal time of a goal is that length over the
controller's speed (``desired_linear_vel`` of the first controller plugin, FollowPath, in the
parameter file the stack runs with).
"""

from __future__ import annotations

import contextlib
import math
import os
import signal
import subprocess
import sys
import threading
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType

import numpy as np
import yaml

from bench.nav_driver import Driver, GoalOutcome
from bench.proc_memory import descendants

REPO = Path(__file__).resolve().parents[1]
MIN_CLEARANCE = 0.4  # m
READY_TIMEOUT = 300.0  # s (wall) for nav-bringup's readiness line
SERVER_TIMEOUT = 60.0  # s (wall) for the action servers and /clock, once the stack is ready
STOP_TIMEOUT = 60.0  # s (wall) nav-bringup may take to stop after SIGINT
PLAN_ATTEMPTS = 200  # unplannable candidates in a row before the session gives up
NEAR_DRAWS = 10_000  # candidates too near the robot before the session gives up


def map_yaml(world: str) -> Path:
    """The map of a sim2d world: maps/<world>.yaml."""
    return REPO / "maps" / f"{world}.yaml"


def free_poses(map_path: Path, min_clearance: float) -> np.ndarray:
    """(N, 2) world positions of free map cells at least ``min_clearance`` m from any non-free cell.

    Distances are between cell centres; cells outside the map do not count as blocked.
    """
    from nav_stack.core.map_io import load_map

    occupancy = load_map(map_path)
    data, spec = occupancy.data, occupancy.spec
    free = data == 0
    blocked = ~free
    height, width = blocked.shape
    reach = math.ceil(min_clearance / spec.resolution)
    near = np.zeros_like(blocked)  # a blocked cell closer than min_clearance
    for dr in range(-reach, reach + 1):
        for dc in range(-reach, reach + 1):
            if math.sqrt(dr * dr + dc * dc) * spec.resolution >= min_clearance:
                continue
            shifted = np.zeros_like(blocked)  # shifted[r, c] = blocked[r + dr, c + dc]
            shifted[max(0, -dr):height - max(0, dr), max(0, -dc):width - max(0, dc)] = \
                blocked[max(0, dr):height + min(0, dr), max(0, dc):width + min(0, dc)]
            near |= shifted
    rows, cols = np.nonzero(free)
    keep = ~near[rows, cols]
    xs, ys = spec.cell_to_world(cols[keep], rows[keep])
    return np.column_stack((xs, ys))


#: A controller plugin's cruise-speed parameter (m/s), by Nav2 class name.
CRUISE_KEYS = {"RegulatedPurePursuitController": "desired_linear_vel", "MPPIController": "vx_max",
               "DWBLocalPlanner": "max_vel_x"}


def ideal_speed(params: Path, robot: str | None = None) -> float:
    """The speed (m/s) the velocity chain lets the robot cruise at: the lowest of its first controller's
    cruise speed (RPP ``desired_linear_vel``, MPPI ``vx_max``, DWB ``max_vel_x``, also behind a rotation
    shim), velocity_smoother's ``max_velocity[0]`` when the file configures it, and ``robot``'s own
    limit (sim2d's model; Nav2's file caps MPPI at 0.5 m/s, the waffle drives at 0.26 m/s)."""
    from nav_stack.ros.bringup.plugin_catalog import class_name

    doc = yaml.safe_load(params.read_text())
    try:
        server = doc["controller_server"]["ros__parameters"]
        plugin = server.get("controller_plugins", ["FollowPath"])[0]
        section = server[plugin]
        kind = class_name(section.get("plugin", "DWBLocalPlanner"))
        if kind == "RotationShimController":
            kind = class_name(section["primary_controller"])
        speeds = [float(section[CRUISE_KEYS[kind]])]
    except (KeyError, TypeError, IndexError, ValueError) as error:
        raise ValueError(f"{params}: controller_server.ros__parameters.<first controller_plugins>: no "
                         f"cruise speed ({', '.join(CRUISE_KEYS.values())}) found ({error!r})") from error
    smoother = (doc.get("velocity_smoother") or {}).get("ros__parameters") or {}
    if "max_velocity" in smoother:
        speeds.append(float(smoother["max_velocity"][0]))
    if robot is not None:
        from sim2d.core.robot import ROBOTS

        speeds.append(ROBOTS[robot].max_linear_velocity)
    return min(speeds)


def _watch(proc: subprocess.Popen[str], ready: threading.Event) -> None:
    """Echo nav-bringup's warnings and errors; set ``ready`` on its readiness line."""
    assert proc.stdout is not None
    for line in proc.stdout:
        if "Nav2 is ready" in line:
            ready.set()
        if "ERROR" in line or "[launch]" in line:
            print(line.rstrip(), flush=True)


class Stack:
    """nav-bringup for one world and robot, and the Driver client on it (a context manager).

    Entering starts nav-bringup and waits until it is ready and the Driver sees its action servers
    and /clock; leaving closes the client and stops nav-bringup (SIGINT, as Ctrl-C would).
    """

    def __init__(self, world: str, robot: str, params: Path, rtf: str, lockstep: bool,
                 client: str = "bench_navigation", extra: Sequence[str] = ()) -> None:
        """``world``: a sim2d world name or file; ``extra``: more nav-bringup options (``--map``).

        The processes log to artifacts/logs/<client>/ (unless ``extra`` names a ``--log-dir``): two
        benchmarks running at once would otherwise write over each other's artifacts/logs/sim2d.log.
        """
        logs = [] if "--log-dir" in extra else ["--log-dir", str(REPO / "artifacts" / "logs" / client)]
        self.command = [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup", "--world", world,
                        "--robot", robot, "--rtf", rtf, "--params", str(params),
                        *([] if lockstep else ["--no-lockstep"]), *logs, *extra]
        self.lockstep = lockstep
        self.client = client
        self.process: subprocess.Popen[str] | None = None
        self._driver: Driver | None = None

    @property
    def driver(self) -> Driver:
        assert self._driver is not None, "the stack is not running"
        return self._driver

    def __enter__(self) -> Stack:
        self.process = subprocess.Popen(self.command, cwd=REPO, stdout=subprocess.PIPE,
                                        stderr=subprocess.STDOUT, text=True)
        ready = threading.Event()
        threading.Thread(target=_watch, args=(self.process, ready), daemon=True).start()
        try:
            if not ready.wait(READY_TIMEOUT):
                raise RuntimeError(f"nav-bringup did not print 'Nav2 is ready' within {READY_TIMEOUT:.0f} s")
            self._driver = Driver(self.lockstep, self.client)
            deadline = time.monotonic() + SERVER_TIMEOUT
            while not self._driver.servers_ready():
                if time.monotonic() > deadline:
                    raise RuntimeError("navigate_to_pose / compute_path_to_pose / clock not available")
                time.sleep(0.1)
        except BaseException:
            traceback.print_exc()  # now, before a teardown that could hang hides it
            self.__exit__(None, None, None)
            raise
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 tb: TracebackType | None) -> None:
        if error is not None:
            traceback.print_exception(error)  # now, before a teardown that could hang hides it
        if self._driver is not None:
            self._driver.close()
            self._driver = None
        if self.process is not None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=STOP_TIMEOUT)
            except subprocess.TimeoutExpired:  # the next stack must not share the domain with this one
                print(f"nav-bringup did not stop within {STOP_TIMEOUT:.0f} s of SIGINT: "
                      "killing its processes", flush=True)
                for pid in reversed(descendants(self.process.pid)):
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(pid, signal.SIGKILL)
                self.process.wait(timeout=STOP_TIMEOUT)
            self.process = None


@dataclass(frozen=True)
class GoalRecord:
    """One goal of a session, as the session saw it when the goal ended."""

    index: int  # 1-based
    goal: tuple[float, float, float]  # x m, y m, yaw rad (map)
    outcome: GoalOutcome
    ideal_s: float  # optimal path length / ideal speed
    navigator_s: float  # navigation_time of the goal's last feedback
    recoveries: int
    wall_s: float  # 0 when the goal was not accepted
    collisions: int  # since the session's first goal
    sim_so_far: float  # sim s since the session's first goal
    wall_so_far: float  # wall s since the session's first goal

    @property
    def ratio(self) -> float:
        """Time to goal over the ideal time."""
        return self.outcome.sim_s / self.ideal_s


@dataclass
class GoalRun:
    """The goals of a session and its totals."""

    records: list[GoalRecord] = field(default_factory=list)
    collisions: int = 0
    sim_s: float = 0.0  # from the first goal's planning to the last goal's result
    wall_s: float = 0.0
    lost_requests: int = 0

    @property
    def succeeded(self) -> list[GoalRecord]:
        return [record for record in self.records if record.outcome.ok]

    @property
    def goal_rtfs(self) -> list[float]:
        """Per-goal real-time factor (sim s / wall s) of every goal that got a result or timed out."""
        return [r.outcome.sim_s / r.wall_s for r in self.records if r.wall_s > 0.0]


def run_goals(driver: Driver, candidates: np.ndarray, rng: np.random.Generator, start: tuple[float, float],
              goals: int, speed: float, on_goal: Callable[[GoalRecord], None],
              stop: Callable[[], bool] = lambda: False, min_distance: float = 0.5) -> GoalRun:
    """Drive ``goals`` random goals from ``start``; ``on_goal`` sees each one as it ends.

    A goal is a random candidate (x, y) at least ``min_distance`` m (straight line) from the robot
    that the planner reaches, with
    a random yaw. After a failure the next plan starts from the robot's true position; after 20
    candidates in a row that cannot be planned from there, from the last goal reached. ``stop`` is
    asked after each goal (e.g. Ctrl-C: finish the current goal, keep what was measured).
    """
    position = last_reached = start
    collisions0, sim0, wall0 = driver.collisions, driver.sim_time, time.monotonic()
    run = GoalRun()
    for index in range(goals):
        attempts = too_near = 0
        while True:
            x, y = candidates[rng.integers(len(candidates))]
            if math.hypot(x - position[0], y - position[1]) < min_distance:
                too_near += 1
                if too_near >= NEAR_DRAWS:
                    raise RuntimeError(f"{NEAR_DRAWS} candidates in a row nearer than {min_distance} m "
                                       f"to {position}")
                continue
            length = driver.path_length(position, (x, y))
            if length is not None and length > 0.0:
                break
            attempts += 1
            if attempts >= 20:  # the robot's real position cannot be planned from (inscribed cell)
                position = last_reached
            if attempts >= PLAN_ATTEMPTS:
                raise RuntimeError(f"no plannable goal in {PLAN_ATTEMPTS} candidates from {position}")
        yaw = float(rng.uniform(-math.pi, math.pi))
        outcome = driver.navigate((x, y, yaw))
        record = GoalRecord(index + 1, (float(x), float(y), yaw), outcome, length / speed,
                            driver.navigation_time, driver.recoveries, driver.wall_s,
                            driver.collisions - collisions0, driver.sim_time - sim0, time.monotonic() - wall0)
        run.records.append(record)
        on_goal(record)
        if outcome.ok:
            position = last_reached = (x, y)
        elif driver.truth is not None:  # the next ideal path starts where the robot really is
            position = driver.truth
        if stop():
            break
    run.sim_s, run.wall_s = driver.sim_time - sim0, time.monotonic() - wall0
    run.collisions = driver.collisions - collisions0
    run.lost_requests = driver.lost_requests
    return run
