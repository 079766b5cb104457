"""Fault matrix (issue 45): each fault kind x {seed state machine, seed tree, 2-goal mission} x N seeds.

Every cell is one scenario of the farm (navsuite_tools/scenarios: the real stack over DDS, in lockstep), with
one fault event injected at ``AT`` s of sim time (shifted by 0.5 s per seed) and sim2d seeded with the
seed, so the seeds see different noise and different moments of the mission. What each run must show
(the issue's bar): it ends (SUCCESS, or a named fault with its Nav2 code; the farm's deadline is the
"hang" bound), and a SUCCESS has the robot within GOAL_TOLERANCE m of its last goal by ground truth
(the end of the last /plan in the recording against the last /ground_truth pose).

Prints a Markdown table (one row per fault and mission, one cell per seed: result, code, final
distance to the goal) and the counts; nothing is written to bench/RESULTS.md.

Usage::

    .venv/bin/python -m bench.bench_faults                        # 5 seeds, 2 workers
    .venv/bin/python -m bench.bench_faults --seeds 1 --faults kill_navigation topic_loss_scan
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

REPO = Path(__file__).resolve().parents[1]
AT = 3.0  # s of sim time of the fault for seed 0 (on the way to the first goal in every mission)
GOAL_TOLERANCE = 0.3  # m: a SUCCESS farther than this from its goal by ground truth is a finding
#: fault kind -> its event (without ``at``): every event kind of the scenario schema, the freeze of the
#: navigation process both shorter and longer than nav-bringup's bond_timeout (10 s)
FAULTS: dict[str, dict[str, Any]] = {
    "kill_navigation": {"kill_navigation": None},
    "kill_localization": {"kill_localization": None},
    "kill_simulator": {"kill_simulator": None},
    "freeze_navigation_2s": {"freeze_navigation": 2.0},
    "freeze_navigation_12s": {"freeze_navigation": 12.0},
    "freeze_localization_12s": {"freeze_localization": 12.0},
    "freeze_simulator_3s": {"freeze_simulator": 3.0},
    "topic_loss_scan": {"topic_loss": {"topic": "scan", "duration": 2.0}},
    "topic_loss_odom": {"topic_loss": {"topic": "odom", "duration": 1.0}},
    "clock_pause_3s": {"clock_pause": 3.0},
    "obstacle_on_path": {"obstacle_on_path": {"ahead": 0.8, "radius": 0.15}},
    "odom_slip": {"odom_slip": {"scale": 1.3, "duration": 5.0}},
}
MISSIONS: dict[str, dict[str, Any]] = {
    "state machine": {"state_machine": "sm_nav2_test_1"},
    "tree": {"behavior_tree": "config/trees/seed_battery_patrol_v3.xml", "locations": "config/locations.yaml",
             "max_cycles": 1},
    "2 goals": {"goals": [[-0.55, -0.55, 0.0], [0.55, -0.55, 1.57]]},
}
MISSION_KEYS = {"state machine": "sm", "tree": "bt", "2 goals": "goals"}


@dataclass(frozen=True)
class Cell:
    """One run's outcome: result word, Nav2 code, detail, final ground-truth distance to the goal (m)."""

    result: str
    code: int | None
    detail: str
    goal_distance: float | None
    events: int
    wall: float

    @property
    def finding(self) -> str:
        """Why this run breaks the issue's bar ('' when it does not)."""
        if self.result == "SUCCESS" and (self.goal_distance is None or self.goal_distance > GOAL_TOLERANCE):
            where = "not measured" if self.goal_distance is None else f"{self.goal_distance:.2f} m"
            return f"SUCCESS but {where} from the goal"
        if self.result in ("TIMEOUT", "ERROR"):
            return f"{self.result}: {self.detail}"
        if self.events == 0:
            return "the fault was not applied"
        return ""

    def text(self) -> str:
        code = "" if self.code is None else f" {self.code}"
        distance = "" if self.goal_distance is None else f", {self.goal_distance:.2f} m"
        return f"{self.result}{code}{distance}"


def scenario_file(faults: list[str], missions: list[str], seeds: int, path: Path) -> list[str]:
    """Write the matrix as a scenario file; the scenario names in order."""
    scenarios: list[dict[str, Any]] = []
    for fault in faults:
        for mission in missions:
            for seed in range(seeds):
                event = {"at": AT + 0.5 * seed, **FAULTS[fault]}
                scenarios.append({"name": f"{fault}.{MISSION_KEYS[mission]}.s{seed}", "seed": seed,
                                  "mission": MISSIONS[mission], "events": [event],
                                  "expect": {"result": None, "max_collisions": None}})
    document = {"defaults": {"world": "turtlebot3_world", "robot": "waffle", "timeout": 150},
                "scenarios": scenarios}
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding="utf-8")
    return [s["name"] for s in scenarios]


def goal_distance(mcap: Path) -> float | None:
    """m between the last ground-truth pose and the end of the last /plan in ``mcap``."""
    from navsuite_tools.bag.reader import BagReader

    with BagReader(mcap) as reader:
        last: dict[str, Any] = {}
        for item, msg in reader.decoded(["/plan", "/ground_truth"]):
            if item.topic != "/plan" or msg.poses:
                last[item.topic] = msg
    if "/plan" not in last or "/ground_truth" not in last:
        return None
    goal = last["/plan"].poses[-1].pose.position
    robot = last["/ground_truth"].pose.pose.position
    return math.hypot(goal.x - robot.x, goal.y - robot.y)


def read_cell(directory: Path) -> Cell:
    data = json.loads((directory / "result.json").read_text(encoding="utf-8"))
    mcap = data.get("artifacts", {}).get("mcap")
    distance = None
    if mcap and Path(mcap).exists():
        try:
            distance = goal_distance(Path(mcap))
        except Exception as error:  # a broken recording: the distance stays unmeasured
            print(f"[faults] {directory.name}: cannot read {mcap}: {error}", flush=True)
    return Cell(data["result"], data.get("result_code"), data.get("detail", ""), distance,
                len(data.get("events_applied", [])), float(data.get("wall_time", 0.0)))


def table(cells: dict[str, Cell], faults: list[str], missions: list[str], seeds: int) -> str:
    lines = ["| fault | mission | " + " | ".join(f"seed {s}" for s in range(seeds)) + " |",
             "|---|---|" + "---|" * seeds]
    for fault in faults:
        for mission in missions:
            row = [cells[f"{fault}.{MISSION_KEYS[mission]}.s{s}"].text()
                   if f"{fault}.{MISSION_KEYS[mission]}.s{s}" in cells else "not run" for s in range(seeds)]
            lines.append(f"| {fault} | {mission} | " + " | ".join(row) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--faults", nargs="+", choices=sorted(FAULTS), default=list(FAULTS))
    parser.add_argument("--missions", nargs="+", choices=list(MISSION_KEYS.values()),
                        default=list(MISSION_KEYS.values()))
    parser.add_argument("--out", type=Path, default=None,
                        help="the farm's output directory (default: a temporary one)")
    args = parser.parse_args(argv)
    missions = [name for name, key in MISSION_KEYS.items() if key in args.missions]
    out = args.out or Path(tempfile.mkdtemp(prefix="bench_faults_"))
    out.mkdir(parents=True, exist_ok=True)
    names = scenario_file(args.faults, missions, args.seeds, out / "fault_matrix.yaml")
    started = time.monotonic()
    subprocess.run([sys.executable, "-m", "navsuite_tools.scenarios.main", "run",
                    str(out / "fault_matrix.yaml"), "--workers", str(args.workers),
                    "--out", str(out / "farm")], cwd=REPO, check=False)
    cells = {name: read_cell(out / "farm" / name) for name in names
             if (out / "farm" / name / "result.json").exists()}
    wall = time.monotonic() - started
    print(f"\n## Fault matrix: {len(cells)} runs, {args.seeds} seed(s), {wall:.0f} s wall\n")
    print("Each cell: result, Nav2 error code, final ground-truth distance to the last goal (m).\n")
    print(table(cells, args.faults, missions, args.seeds))
    findings = {name: cell.finding for name, cell in cells.items() if cell.finding}
    counts: dict[str, int] = {}
    for cell in cells.values():
        counts[cell.result] = counts.get(cell.result, 0) + 1
    print("\nresults: " + ", ".join(f"{word} {n}" for word, n in sorted(counts.items())))
    print(f"findings ({len(findings)}):" + "".join(f"\n- {name}: {why}" for name, why in findings.items()))
    for name, cell in cells.items():
        print(f"[detail] {name}: {cell.result} ({cell.detail}) wall {cell.wall:.0f} s", flush=True)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
