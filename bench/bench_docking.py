"""Docking from random poses through the whole stack (nav-bringup with docking_server), judged by sim2d.

Each of ``--dockings`` rounds (20 by default, seeded): NavigateToPose to a random free pose at least
``--min-distance`` (2 m) from the dock, then DockRobot ``home_dock`` (navigate_to_staging_pose true,
as the patrol docks), then UndockRobot so the next round starts clear. Judged by sim2d's ground truth
(``ground_truth``, nav_msgs/Odometry in map): a docking counts when the action succeeded, base_link
ends within 2 cm and 0.05 rad of the dock's contact pose (the world file's ``docks`` entry) and
``/battery_state`` reported CHARGING. Also recorded: the median time to dock (sim s and wall s, from
sending the goal to its result), collisions (sim2d/collision_count over the rounds, navigation
included) and the undockings.

The stack runs with the robot's parameter file and the world's dock file as a second ``--params``
(config/docks/<world>.yaml), in lockstep at ``--rtf max`` by default.

    .venv/bin/python -m bench.bench_docking [--dockings 20] [--seed 3] [--world turtlebot3_world]
                                            [--rtf max] [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import math
import statistics
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note
from bench.nav_driver import HOLD_GRACE, Driver
from bench.nav_session import MIN_CLEARANCE, Stack, free_poses, map_yaml

REPO = Path(__file__).resolve().parents[1]
DOCK_ID = "home_dock"
POSITION_TOLERANCE, YAW_TOLERANCE = 0.02, 0.05  # m, rad: what counts as docked on the contact pose
ACTION_TIMEOUT = 300.0  # wall s for one dock or undock goal


@dataclass(frozen=True)
class DockingRecord:
    """One round: the action's answer and what the simulator saw (m, rad, s)."""

    index: int
    start: tuple[float, float, float]
    succeeded: bool
    error_code: int
    error_msg: str
    num_retries: int
    position_error: float
    yaw_error: float
    charging: bool
    sim_s: float
    wall_s: float
    undocked: bool

    @property
    def docked(self) -> bool:
        return (self.succeeded and self.charging and self.position_error <= POSITION_TOLERANCE
                and abs(self.yaw_error) <= YAW_TOLERANCE)


class DockingProbe:
    """DockRobot / UndockRobot clients, the full ground-truth pose and the charging status, on the
    Driver's node (spun by its thread)."""

    def __init__(self, driver: Driver) -> None:
        from nav2_msgs.action import DockRobot, UndockRobot
        from nav_msgs.msg import Odometry
        from sensor_msgs.msg import BatteryState

        from ros_tools.runtime.actions import ActionClient

        self.driver = driver
        node = driver.node
        self.dock_client = ActionClient(node, DockRobot, "dock_robot")
        self.undock_client = ActionClient(node, UndockRobot, "undock_robot")
        self.pose: tuple[float, float, float] | None = None
        self.charging_seen = False
        node.create_subscription(Odometry, "ground_truth", self._on_truth, 10)
        node.create_subscription(BatteryState, "battery_state", self._on_battery, 10)

    def _on_truth(self, msg: Any) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.pose = (p.x, p.y, math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z)))

    def _on_battery(self, msg: Any) -> None:
        from sensor_msgs.msg import BatteryState

        if msg.power_supply_status in (BatteryState.POWER_SUPPLY_STATUS_CHARGING,
                                       BatteryState.POWER_SUPPLY_STATUS_FULL) and msg.current > 0.0:
            self.charging_seen = True

    def ready(self) -> bool:
        return bool(self.dock_client.server_is_ready() and self.undock_client.server_is_ready())

    def run(self, client: Any, goal: Any) -> tuple[Any, float, float]:
        """Send ``goal`` and wait for its result: (response or None, sim s, wall s)."""
        driver = self.driver
        sim0, wall0 = driver.sim_time, time.monotonic()
        ended: list[float] = []
        outcome: list[Any] = []

        def on_result(future: Any) -> None:
            ended.append(driver.sim_time)

        def on_accepted(future: Any) -> None:
            handle = future.result()
            if handle is not None and handle.accepted:
                result = handle.get_result_async()
                outcome.append(result)
                result.add_done_callback(on_result)

        requests: list[Any] = []
        if driver.lockstep is not None:  # the request's DDS latency is not docking time
            driver.lockstep.hold(lambda: bool(requests) and requests[0].done(), HOLD_GRACE)
        sent = client.send_goal_async(goal)
        requests.append(sent)
        sent.add_done_callback(on_accepted)
        deadline = time.monotonic() + ACTION_TIMEOUT
        while not ended and time.monotonic() < deadline:
            time.sleep(0.02)
        if not ended:
            if sent.done() and sent.result() is not None:
                sent.result().cancel_goal_async()
            return None, driver.sim_time - sim0, time.monotonic() - wall0
        return outcome[0].result(), ended[0] - sim0, time.monotonic() - wall0


def contact_pose(world: str) -> tuple[float, float, float]:
    """The contact pose of ``home_dock`` in the sim2d world's file."""
    import yaml

    path = REPO / "sim2d" / "worlds" / f"{world}.yaml"
    docks = yaml.safe_load(path.read_text()).get("docks") or []
    for dock in docks:
        if dock.get("id") == DOCK_ID:
            x, y, yaw = (float(v) for v in dock["pose"])
            return x, y, yaw
    raise SystemExit(f"{path}: no dock '{DOCK_ID}'")


def dock_round(index: int, start: tuple[float, float, float], probe: DockingProbe,
               contact: tuple[float, float, float]) -> DockingRecord:
    """Dock (the robot stands at ``start``), then undock."""
    from nav2_msgs.action import DockRobot, UndockRobot

    probe.charging_seen = False
    goal = DockRobot.Goal(use_dock_id=True, dock_id=DOCK_ID, navigate_to_staging_pose=True,
                          max_staging_time=1000.0)
    response, sim_s, wall_s = probe.run(probe.dock_client, goal)
    time.sleep(0.3)  # wall: the last ground truth and battery reading after the result
    x, y, yaw = probe.pose or (math.nan, math.nan, math.nan)
    error = math.hypot(x - contact[0], y - contact[1])
    yaw_error = math.remainder(yaw - contact[2], math.tau)
    undock, _, _ = probe.run(probe.undock_client, UndockRobot.Goal(max_undocking_time=30.0))
    undocked = undock is not None and bool(undock.result.success)
    if response is None:
        return DockingRecord(index, start, False, -1, "no result", 0, error, yaw_error, probe.charging_seen,
                             sim_s, wall_s, undocked)
    result = response.result
    return DockingRecord(index, start, bool(result.success), int(result.error_code), str(result.error_msg),
                         int(result.num_retries), error, yaw_error, probe.charging_seen, sim_s, wall_s,
                         undocked)


def starts(world: str, contact: tuple[float, float, float], count: int, min_distance: float,
           rng: np.random.Generator) -> list[tuple[float, float, float]]:
    """``count`` random free poses (0.4 m clearance) at least ``min_distance`` m from the dock."""
    candidates = free_poses(map_yaml(world), MIN_CLEARANCE)
    far = candidates[np.hypot(candidates[:, 0] - contact[0], candidates[:, 1] - contact[1]) >= min_distance]
    picks = rng.choice(len(far), size=count, replace=False)
    return [(float(far[i, 0]), float(far[i, 1]), float(rng.uniform(-math.pi, math.pi))) for i in picks]


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dockings", type=int, default=20)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--world", default="turtlebot3_world")
    parser.add_argument("--robot", default="waffle")
    parser.add_argument("--min-distance", type=float, default=2.0, help="m from the dock to each start")
    parser.add_argument("--rtf", default="max")
    parser.add_argument("--dock-params", type=Path, default=None,
                        help="the docking_server file (default config/docks/<world>.yaml)")
    parser.add_argument("--note", default="")
    parser.add_argument("--log-dir", type=Path, default=None,
                        help="where the stack's processes log (default artifacts/logs/bench_docking/)")
    parser.add_argument("--no-record", action="store_true")
    return parser


def _print(record: DockingRecord, total: int) -> None:
    x, y, _ = record.start
    verdict = "ok  " if record.docked else "FAIL"
    print(f"docking {record.index:2d}/{total} from ({x:5.2f}, {y:5.2f}): {verdict} code {record.error_code} "
          f"retries {record.num_retries}, error {100 * record.position_error:.1f} cm "
          f"{record.yaw_error:+.3f} rad, charging {record.charging}, {record.sim_s:.1f} s sim "
          f"{record.wall_s:.1f} s wall, undocked {record.undocked}"
          + (f" - {record.error_msg}" if record.error_msg else ""), flush=True)


def record_rows(bench: Benchmark, records: list[DockingRecord], collisions: int, note: str) -> None:
    docked = [r for r in records if r.docked]
    n = len(records)
    bench.record_value("docked within 2 cm and 0.05 rad, charging", float(len(docked)), f"of {n}", note)
    bench.record_value("charging seen", float(sum(r.charging for r in records)), f"of {n}", note)
    bench.record_value("collisions", float(collisions), "count", f"{note}; navigation, docking and undocking")
    bench.record_value("undocked", float(sum(r.undocked for r in records)), f"of {n}", note)
    if docked:
        bench.record_value("time to dock (median, sim)", statistics.median(r.sim_s for r in docked), "s",
                           f"{note}; goal sent to result, staging navigation included")
        bench.record_value("time to dock (median, wall)", statistics.median(r.wall_s for r in docked), "s",
                           note)
        errors = [r.position_error for r in docked]
        bench.record_value("position error at the contact pose (median)", 100 * statistics.median(errors),
                           "cm", f"{note}; max {100 * max(errors):.1f} cm, max |yaw error| "
                           f"{max(abs(r.yaw_error) for r in docked):.3f} rad")


def main() -> int:
    from nav_stack.ros.bringup.robot_params import params_for_robot

    args = _parser().parse_args()
    domain = enter_local_domain()
    version = code_version_with_fingerprint()
    print(f"docking: ROS_DOMAIN_ID {domain}, code {version}", flush=True)
    dock_params = args.dock_params or REPO / "config" / "docks" / f"{args.world}.yaml"
    contact = contact_pose(args.world)
    rng = np.random.default_rng(args.seed)
    poses = starts(args.world, contact, args.dockings, args.min_distance, rng)
    interrupted = threading.Event()
    records: list[DockingRecord] = []
    with Stack(args.world, args.robot, params_for_robot(args.robot), args.rtf, True, "bench_docking",
               extra=["--params", str(dock_params),
                      *(["--log-dir", str(args.log_dir)] if args.log_dir else [])]) as stack:
        driver = stack.driver
        probe = DockingProbe(driver)
        deadline = time.monotonic() + 60.0
        while not probe.ready():
            if time.monotonic() > deadline:
                raise SystemExit("dock_robot / undock_robot not available: is docking_server configured?")
            time.sleep(0.1)
        collisions0 = driver.collisions
        for index, start in enumerate(poses, 1):
            if interrupted.is_set():
                break
            outcome = driver.navigate(start)
            if not outcome.ok:
                print(f"docking {index:2d}: navigation to the start failed ({outcome.message}); docking from "
                      "where the robot stands", flush=True)
            records.append(dock_round(index, start, probe, contact))
            _print(records[-1], args.dockings)
        collisions = driver.collisions - collisions0
    note = (f"{len(records)} dockings from random poses >= {args.min_distance:g} m from the dock, "
            f"seed {args.seed}, {args.world}/{args.robot}, rtf {args.rtf} lockstep, "
            f"params {dock_params.name} over the robot's, "
            f"{version_note(version)}" + (f"; {args.note}" if args.note else ""))
    bench = Benchmark("docking")
    record_rows(bench, records, collisions, note)
    if not args.no_record:
        bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
