"""The seed's docking patrol for hours of sim time with the robot's real battery: does it last?

nav-autonomy runs config/trees/seed_battery_patrol_docking.xml against nav-bringup (turtlebot3_world, the
waffle, its dock database config/docks/turtlebot3_world.yaml) in lockstep at ``--rtf max`` for
``--sim-hours`` (default 4) of sim time. Both take config/autonomy_docking_realistic.yaml: the waffle's
pack as config/sim2d.yaml has it (1.8 Ah; 0.011 % per metre and per second: about 2 h of driving) charged
at 1C (the reported 1.8 A into 1.8 Ah: 1/3600 per s, 45 min from 20 % to 95 %) on the dock's contacts.
``--initial-charge`` starts lower and ``--charged-threshold`` undocks earlier (a short run that still
docks, charges and undocks); the row's note says so.

Observed through the graph only, from this process:

* patrol rounds: ``go_to_location4`` turning SUCCESS on /behavior_tree_log (the autonomy's tree);
* goals: the ``_action/status`` topics of navigate_to_pose (the patrol's legs and docking_server's
  staging), dock_robot and undock_robot. A goal is sent when its id first appears, and ends with its
  first terminal status; "hanging" is a goal still listed without a terminal status after the autonomy
  was stopped (SIGINT: it cancels its running goal) and the servers had STOP_GRACE to answer;
* dockings and undockings: dock_robot / undock_robot goals that succeeded; /battery_state's CHARGING
  starts as a cross-check;
* low-battery episodes: from the first /battery_state at or below ``low_threshold`` to the next
  successful docking. One still open at the end counts as pending when it began less than DOCK_GRACE of
  sim time before the end (the leg under way, then the docking), else as missed;
* collisions: sim2d/collision_count, and where each one was (sim2d/collisions).

A progress line every 10 sim minutes. Exit code 0 only when no goal hangs, there was no collision and no
low-battery episode was missed.

    .venv/bin/python -m bench.bench_dock_patrol [--sim-hours 4] [--rtf max] [--initial-charge 1.0]
                                                [--charged-threshold 0.95] [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bench.dock_patrol_tally import (
    ABORTED,
    ACTIONS,
    CANCELED,
    DOCK_GRACE,
    SUCCEEDED,
    PatrolTally,
    progress_line,
)
from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note

REPO = Path(__file__).resolve().parents[1]
CONFIG = REPO / "config" / "autonomy_docking_realistic.yaml"
DOCKS = REPO / "config" / "docks" / "turtlebot3_world.yaml"
LOGS = REPO / "artifacts" / "logs" / "bench_dock_patrol"
PROGRESS_PERIOD = 600.0  # sim s between two progress lines
STALL_LIMIT = 180.0  # wall s without sim time moving before the run is given up
STOP_GRACE = 30.0  # wall s the servers have to answer the goals in flight once the autonomy stopped


class Observer:
    """The tally's subscriptions, on the Driver's node (spun by its thread)."""

    def __init__(self, driver: Any, tally: PatrolTally) -> None:
        from action_msgs.msg import GoalStatusArray
        from geometry_msgs.msg import PointStamped
        from nav2_msgs.msg import BehaviorTreeLog
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from sensor_msgs.msg import BatteryState

        self.driver, self.tally = driver, tally
        self.lock = threading.Lock()
        status_qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                                durability=DurabilityPolicy.TRANSIENT_LOCAL)  # as action servers offer it
        node = driver.node
        for action in ACTIONS:
            node.create_subscription(GoalStatusArray, f"/{action}/_action/status",
                                     lambda msg, action=action: self._on_status(action, msg), status_qos)
        node.create_subscription(BehaviorTreeLog, "/behavior_tree_log", self._on_tree, 100)
        node.create_subscription(BatteryState, "/battery_state", self._on_battery, 10)
        node.create_subscription(PointStamped, "/sim2d/collisions", self._on_collision, 10)
        self._charging = BatteryState.POWER_SUPPLY_STATUS_CHARGING

    def _on_status(self, action: str, msg: Any) -> None:
        statuses = [(bytes(s.goal_info.goal_id.uuid), int(s.status)) for s in msg.status_list]
        with self.lock:
            self.tally.on_statuses(action, statuses, self.driver.sim_time)

    def _on_tree(self, msg: Any) -> None:
        with self.lock:
            for event in msg.event_log:
                self.tally.on_tree_event(event.node_name, event.current_status)

    def _on_battery(self, msg: Any) -> None:
        with self.lock:
            self.tally.on_battery(float(msg.percentage), msg.power_supply_status == self._charging,
                                  self.driver.sim_time)

    def _on_collision(self, msg: Any) -> None:
        with self.lock:
            self.tally.collisions.append((self.driver.sim_time, msg.point.x, msg.point.y))
        print(f"dock_patrol: COLLISION at ({msg.point.x:.2f}, {msg.point.y:.2f}), sim "
              f"{self.driver.sim_time:.1f} s", flush=True)


def start_autonomy(log: Path, overrides: dict[str, float]) -> subprocess.Popen[bytes]:
    """nav-autonomy with the realistic file (and ``overrides`` of its parameters), its output to ``log``."""
    log.parent.mkdir(parents=True, exist_ok=True)
    with log.open("wb") as out:
        command = [sys.executable, "-m", "nav_stack.ros.autonomy.node", "--ros-args",
                   "--params-file", str(CONFIG)]
        command += [arg for name, value in overrides.items() for arg in ("-p", f"{name}:={value}")]
        return subprocess.Popen(command, cwd=REPO, stdout=out, stderr=subprocess.STDOUT)


def stop_autonomy(proc: subprocess.Popen[bytes]) -> int | None:
    """SIGINT (the node cancels its running goal), then SIGKILL after 60 s; the exit code."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=60.0)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    return proc.returncode


@dataclass(frozen=True)
class Span:
    """What the run covered: sim s (the simulator's clock) and wall s, and how it ended."""

    sim0: float
    sim1: float
    wall_s: float
    ended: str

    @property
    def sim_s(self) -> float:
        return self.sim1 - self.sim0

    @property
    def completed(self) -> bool:
        return self.ended.endswith("done")


def patrol(driver: Any, observer: Observer, sim_hours: float, overrides: dict[str, float]) -> Span:
    """Run the autonomy for ``sim_hours`` of sim time (or until it stalls or exits), then stop it."""
    proc = start_autonomy(LOGS / "autonomy.log", overrides)
    sim0, wall0 = driver.sim_time, time.monotonic()
    next_line, ended = PROGRESS_PERIOD, f"{sim_hours:g} sim h done"
    last_sim, last_move = sim0, wall0
    try:
        while driver.sim_time - sim0 < sim_hours * 3600.0:
            time.sleep(0.5)
            now = time.monotonic()
            if driver.sim_time != last_sim:
                last_sim, last_move = driver.sim_time, now
            if now - last_move > STALL_LIMIT:
                ended = f"STALLED: sim time stood still for {STALL_LIMIT:.0f} wall s"
                break
            if proc.poll() is not None:
                ended = f"AUTONOMY EXITED with code {proc.returncode}"
                break
            if driver.sim_time - sim0 >= next_line:
                next_line += PROGRESS_PERIOD
                with observer.lock:
                    print(progress_line(observer.tally, driver.sim_time - sim0, now - wall0), flush=True)
    except KeyboardInterrupt:
        ended = "INTERRUPTED"
    span = Span(sim0, driver.sim_time, time.monotonic() - wall0, ended)
    code = stop_autonomy(proc)
    print(f"dock_patrol: {ended}; autonomy stopped (exit {code}) at sim {span.sim_s / 3600:.2f} h",
          flush=True)
    deadline = time.monotonic() + STOP_GRACE
    while time.monotonic() < deadline:
        with observer.lock:
            if not observer.tally.totals()["hanging"]:
                break
        time.sleep(0.2)
    return span


def record_rows(bench: Benchmark, tally: PatrolTally, span: Span, note: str) -> None:
    t = tally.totals()
    docked, pending, missed = tally.episode_counts(span.sim1)
    per_action = "; ".join(f"{name} {len(g.last)} sent, {g.count(SUCCEEDED)} ok, {g.count(ABORTED)} failed, "
                           f"{g.count(CANCELED)} canceled, {g.in_flight} hanging"
                           for name, g in tally.goals.items())
    bench.record_value("patrol rounds", tally.rounds, "count", note)
    bench.record_value("dockings", tally.dockings(), "count",
                       f"{note}; charging started {tally.charging_starts} times on /battery_state")
    bench.record_value("undockings", tally.goals["undock_robot"].count(SUCCEEDED), "count", note)
    bench.record_value("low-battery episodes with a docking", docked, f"of {docked + pending + missed}",
                       f"{note}; {pending} pending at the end (began < {DOCK_GRACE:.0f} sim s before), "
                       f"{missed} missed")
    bench.record_value("lowest charge seen", 100 * tally.lowest_charge, "%", note)
    bench.record_value("goals sent", t["sent"], "count", f"{note}; {per_action}")
    bench.record_value("goals succeeded", t["succeeded"], "count", note)
    bench.record_value("goals failed", t["failed"], "count", f"{note}; {t['canceled']} canceled (the stop)")
    bench.record_value("goals left hanging", t["hanging"], "count",
                       f"{note}; ends not seen on the status topic: {t['unseen']}")
    bench.record_value("collisions", len(tally.collisions), "count", note)
    bench.record_value("sim hours", span.sim_s / 3600.0, "h", note)
    bench.record_value("wall minutes", span.wall_s / 60.0, "min",
                       f"{note}; autonomy start to stop, stack start excluded")
    bench.record_value("real-time factor", span.sim_s / span.wall_s, "x", note)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sim-hours", type=float, default=4.0)
    parser.add_argument("--rtf", default="max", help="nav-bringup --rtf (lockstep)")
    parser.add_argument("--initial-charge", type=float, default=None,
                        help="start below the file's full charge (said in the note)")
    parser.add_argument("--charged-threshold", type=float, default=None,
                        help="undock at this charge instead of the file's (said in the note)")
    parser.add_argument("--note", default="")
    parser.add_argument("--no-record", action="store_true")
    return parser


def _sim_params(initial_charge: float | None) -> Path:
    """The realistic file, or a copy under artifacts/ with another initial charge."""
    if initial_charge is None:
        return CONFIG
    import yaml

    doc = yaml.safe_load(CONFIG.read_text())
    doc["sim2d"]["ros__parameters"]["battery"]["initial_charge"] = initial_charge
    path = LOGS / "sim2d_initial_charge.yaml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump({"sim2d": doc["sim2d"]}))
    return path


def main() -> int:
    import yaml

    from bench.nav_session import Stack
    from nav_stack.ros.bringup.robot_params import params_for_robot

    args = _parser().parse_args()
    domain = enter_local_domain()
    version = code_version_with_fingerprint()
    print(f"dock_patrol: ROS_DOMAIN_ID {domain}, code {version}", flush=True)
    autonomy = yaml.safe_load(CONFIG.read_text())["autonomy_node"]["ros__parameters"]
    overrides = {} if args.charged_threshold is None else {"charged_threshold": args.charged_threshold}
    autonomy.update(overrides)
    tally = PatrolTally(float(autonomy["low_threshold"]))
    extra = ["--params", str(DOCKS), "--sim-params", str(_sim_params(args.initial_charge)),
             "--log-dir", str(LOGS)]
    with Stack("turtlebot3_world", "waffle", params_for_robot("waffle"), args.rtf, True, "bench_dock_patrol",
               extra=extra) as stack:
        observer = Observer(stack.driver, tally)
        collisions0 = stack.driver.collisions
        span = patrol(stack.driver, observer, args.sim_hours, overrides)
        counted = stack.driver.collisions - collisions0
    if counted != len(tally.collisions):
        print(f"dock_patrol: sim2d/collision_count says {counted}, {len(tally.collisions)} events heard",
              flush=True)
    charge = "full" if args.initial_charge is None else f"from {100 * args.initial_charge:g} %"
    note = (f"{args.sim_hours:g} sim h asked, {span.ended}; turtlebot3_world/waffle, "
            f"seed_battery_patrol_docking.xml, waffle pack {charge} (1.8 Ah, 0.011 %/m + 0.011 %/s, charged "
            f"at 1C = 1.8 A), thresholds {autonomy['low_threshold']}/{autonomy['charged_threshold']}"
            f"{' (charged threshold lowered)' if overrides else ''}, "
            f"rtf {args.rtf} lockstep, {version_note(version)}" + (f"; {args.note}" if args.note else ""))
    bench = Benchmark("dock_patrol")
    with observer.lock:
        record_rows(bench, tally, span, note)
        reasons = tally.failures(span.sim1)
    if not span.completed:
        reasons.append(span.ended)
    if not args.no_record:
        bench.save()
    print("dock_patrol: " + ("FAIL: " + "; ".join(reasons) if reasons else "PASS"), flush=True)
    return 1 if reasons else 0


if __name__ == "__main__":
    raise SystemExit(main())
