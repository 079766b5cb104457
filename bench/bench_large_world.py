"""Warehouse-scale navigation (issue 19): goals more than 20 m apart through the whole stack in a
generated office of more than 1.5 million map cells, and how often planning overran its budget.

The world is drawn by the office generator (scripts/generate_office_world.py, seeded) and its map is
rasterised at 3 cm (scripts/generate_world_map.py); both go to artifacts/bench_large_world/, not to
the repository. nav-bringup runs it in lockstep at ``--rtf max`` with the robot's own parameters
(the tb4 by default: its 12 m RPLIDAR sees the long hall's ends, where a 3.5 m LDS would see two
parallel walls) and GridBased's search chosen by ``--search`` (A* by default, which maps this size
need; the shipped files keep Nav2's Dijkstra). Each goal is a free cell (>= 0.4 m clearance) at least
``--min-distance`` m in a straight line from the robot, reachable per the running planner
(bench.nav_session).

Recorded: success rate, collisions, the planner server's budget warnings ("planning took ... more
than the ... of expected_planner_frequency", counted in the stack's logs: the target is none), the
sustained real-time factor and the map's size. Targets (issue 19): every goal reached, 0 warnings.
Also (issue 44) the CPU seconds per sim second of each process of the stack (sim2d, the nav2 process,
the launcher...) over the goals, sampled from /proc as bench.bench_cpu does, so a change shows which
process it relieved.

    .venv/bin/python -m bench.bench_large_world [--goals 5] [--width 45] [--height 30]
                                                [--resolution 0.03] [--min-distance 20] [--robot tb4]
                                                [--search astar] [--seed 3] [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import yaml

from bench.bench_cpu import POLL_S, Sampler, process_name
from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note
from bench.nav_session import MIN_CLEARANCE, REPO, GoalRecord, Stack, free_poses, ideal_speed, run_goals

OUT = REPO / "artifacts" / "bench_large_world"
BUDGET_WARNING = "of expected_planner_frequency"  # planner_server's warning when a plan overruns


def _parser() -> argparse.ArgumentParser:
    from nav_stack.ros.bringup.robot_params import ROBOTS

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--goals", type=int, default=5)
    parser.add_argument("--width", type=float, default=45.0, help="office size along x inside its walls (m)")
    parser.add_argument("--height", type=float, default=30.0, help="office size along y inside its walls (m)")
    parser.add_argument("--resolution", type=float, default=0.03, help="map cell size (m)")
    parser.add_argument("--min-distance", type=float, default=20.0,
                        help="straight-line distance of each goal from the robot (m)")
    parser.add_argument("--robot", default="tb4", choices=ROBOTS)
    parser.add_argument("--search", default="astar", choices=("astar", "dijkstra"),
                        help="GridBased's search (default astar: the shipped files keep Nav2's Dijkstra)")
    parser.add_argument("--seed", type=int, default=3, help="draws the office and the goals")
    parser.add_argument("--incremental-costmaps", action="store_true",
                        help="always_send_full_costmap false in both costmaps (the shipped files keep "
                             "the Jazzy yaml's true): full grids once, then costmap_updates (issue 44)")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    return parser


def generate(args: argparse.Namespace) -> tuple[Path, Path]:
    """Write the office world and its map under OUT; (world YAML, map YAML)."""
    OUT.mkdir(parents=True, exist_ok=True)
    name = f"office_{args.width:g}x{args.height:g}_seed{args.seed}"
    world, map_path = OUT / f"{name}.yaml", OUT / f"{name}_map.yaml"
    scripts = REPO / "scripts"
    for command in (
        [scripts / "generate_office_world.py", "--seed", str(args.seed), "--width", str(args.width),
         "--height", str(args.height), "--out", world, "--name", name],
        [scripts / "generate_world_map.py", "--world", world, "--resolution", str(args.resolution),
         "--out", map_path],
    ):
        subprocess.run([sys.executable, *map(str, command)], cwd=REPO, check=True)
    return world, map_path


def planner_params(robot_params: Path, astar: bool, incremental_costmaps: bool = False) -> Path:
    """The robot's parameter file with GridBased's ``use_astar`` set (and ``always_send_full_costmap``
    false in both costmaps with ``incremental_costmaps``), written under OUT."""
    doc = yaml.safe_load(robot_params.read_text())
    doc["planner_server"]["ros__parameters"]["GridBased"]["use_astar"] = astar
    if incremental_costmaps:
        for name in ("global_costmap", "local_costmap"):
            doc[name][name]["ros__parameters"]["always_send_full_costmap"] = False
    suffix = "_incremental" if incremental_costmaps else ""
    path = OUT / f"{robot_params.stem}_{'astar' if astar else 'dijkstra'}{suffix}.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def _cells(map_path: Path) -> int:
    from nav_stack.core.map_io import load_map

    return int(load_map(map_path).data.size)


def _print_goal(record: GoalRecord, goals: int) -> None:
    outcome = record.outcome
    x, y, _ = record.goal
    print(f"goal {record.index}/{goals} ({x:6.2f}, {y:6.2f}): {'ok ' if outcome.ok else 'FAIL'} "
          f"{outcome.sim_s:6.1f} s sim, ideal {record.ideal_s:5.1f} s, recoveries {record.recoveries}, "
          f"collisions {record.collisions}" + ("" if outcome.ok else f" - {outcome.message}"), flush=True)


def budget_warnings(log_dir: Path) -> list[str]:
    """The planner server's over-budget lines in every process log under ``log_dir``."""
    return [line.strip() for log in sorted(log_dir.glob("*.log"))
            for line in log.read_text(errors="replace").splitlines() if BUDGET_WARNING in line]


def _sample_until(sampler: Sampler, stop: threading.Event) -> None:
    while not stop.wait(POLL_S):
        sampler.sample()


def cpu_per_process(sampler: Sampler) -> dict[str, float]:
    """CPU seconds each named process used between the snapshots "start" and "end" (summed by name)."""
    used: dict[str, float] = {}
    start, end = sampler.snapshots["start"], sampler.snapshots["end"]
    for pid, cpu in end.items():
        name = process_name(sampler.last[pid][0])
        used[name] = used.get(name, 0.0) + cpu - start.get(pid, 0.0)
    return used


def main() -> int:
    from nav_stack.ros.bringup.robot_params import params_for_robot
    from nav_stack.ros.bringup.world_defaults import world_defaults

    args = _parser().parse_args()
    domain = enter_local_domain()
    version = code_version_with_fingerprint()
    world, map_path = generate(args)
    cells = _cells(map_path)
    print(f"large_world: {world.name}, map {cells / 1e6:.2f} M cells at {args.resolution} m; "
          f"ROS_DOMAIN_ID {domain}; code {version}", flush=True)
    params = planner_params(params_for_robot(args.robot), args.search == "astar", args.incremental_costmaps)
    log_dir = OUT / "logs"
    for old in log_dir.glob("*.log"):
        old.unlink()
    rng = np.random.default_rng(args.seed)
    candidates = free_poses(map_path, MIN_CLEARANCE)
    start = world_defaults(str(world)).spawn[:2]
    bench = Benchmark("large_world")
    extra = ("--map", str(map_path), "--log-dir", str(log_dir))
    stop = threading.Event()
    with Stack(str(world), args.robot, params, "max", True, "bench_large_world", extra) as stack:
        assert stack.process is not None
        sampler = Sampler(stack.process.pid)
        threading.Thread(target=_sample_until, args=(sampler, stop), daemon=True).start()
        sampler.snapshot("start")
        run = run_goals(stack.driver, candidates, rng, start, args.goals, ideal_speed(params, args.robot),
                        lambda record: _print_goal(record, args.goals), min_distance=args.min_distance)
        sampler.snapshot("end")
        stop.set()
    warnings = budget_warnings(log_dir)
    for line in warnings[:10]:
        print(f"large_world: {line}", flush=True)
    note = (f"{world.stem} ({cells / 1e6:.2f} M cells at {args.resolution} m), {args.robot}, {args.search}, "
            + ("always_send_full_costmap false, " if args.incremental_costmaps else "")
            + f"{len(run.records)}/{args.goals} goals >= {args.min_distance:g} m apart, seed {args.seed}, "
            f"rtf max, lockstep, {version_note(version)}" + (f"; {args.note}" if args.note else ""))
    bench.record_value("goals reached", 100.0 * len(run.succeeded) / max(len(run.records), 1), "%", note)
    bench.record_value("collisions", float(run.collisions), "count", note)
    bench.record_value("planner budget warnings", float(len(warnings)), "count", note)
    bench.record_value("sustained real-time factor", run.sim_s / run.wall_s, "x",
                       f"{note}; {run.sim_s:.0f} sim s in {run.wall_s:.0f} wall s")
    for name, cpu in sorted(cpu_per_process(sampler).items()):
        bench.record_value(f"CPU s per sim s: {name}", cpu / max(run.sim_s, 1e-9), "s/s",
                           f"{note}; over the goals")
    if not args.no_record:
        bench.save()
    return 0 if len(run.succeeded) == len(run.records) and not warnings else 1


if __name__ == "__main__":
    raise SystemExit(main())
