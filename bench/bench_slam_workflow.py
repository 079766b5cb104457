"""The SLAM workflow end to end in one world: explore and map, then navigate on the saved map.

What a user does (README, SLAM section), timed and scored:

1. ``nav-bringup --slam --world W --rtf max --participant explore`` (lockstep) and
   ``nav-explore -f DIR/map --max-time T`` until exploration is complete: sim and wall time,
   goals, mapped area (nav-explore's last progress line);
2. the saved map's occupied cells against the walls of maps/W.yaml that a lidar can see from the
   world's first spawn (IoU with a one-cell tolerance, navsuite_testing/slam/stack.py);
3. the slam node's wall time per processed scan callback, from the summaries it logs every 100
   scans (median of their medians, and the overall max): a callback over the lifecycle manager's
   bond timeout (4 s) gets the node reset and its map lost, which is why this is watched;
4. ``nav-bringup --world W --map DIR/map.yaml`` (AMCL on the saved map) and ``nav-goal goto`` to
   three of the world's spawns across it, one after the other: goals reached.

``--seed`` is sim2d's noise seed (lidar and odometry). Each run claims its own ROS_DOMAIN_ID
(bench/harness.claim_domain_id) with localhost discovery; medians over ``--runs`` are recorded.
Run: ``.venv/bin/python -m bench.bench_slam_workflow --world turtlebot3_house [--runs 1] [--seed 2]
[--max-time 1500] [--no-record]``. Minutes of wall time per run; best on an otherwise idle machine.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench.harness import Benchmark, Stats, claim_domain_id
from navsuite_testing.slam.stack import compare_with_reference, progress_numbers
from sim2d.core.world import load_world

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
READY_LINE = "Nav2 is ready"
TIMING = re.compile(r"last \d+ scans: median (\d+) ms, max (\d+) ms")
STOP_WAIT = 20.0  # s (wall) a launch gets to exit after SIGINT before it is killed
GOAL_TIMEOUT = 600.0  # s (wall) for one nav-goal on a loaded machine


def _start(args: list[str], log: Path, env: dict[str, str]) -> subprocess.Popen[str]:
    return subprocess.Popen([str(BIN / args[0]), *args[1:]], stdout=log.open("w"), stderr=subprocess.STDOUT,
                            text=True, env=env, cwd=REPO, start_new_session=True)


def _stop(proc: subprocess.Popen[str]) -> None:
    """SIGINT to the launch's process group (it stops its children), SIGKILL if it lingers."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(STOP_WAIT)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _wait_ready(proc: subprocess.Popen[str], log: Path, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while READY_LINE not in log.read_text():
        if proc.poll() is not None or time.monotonic() > deadline:
            raise SystemExit(f"nav-bringup did not get ready (see {log})")
        time.sleep(0.5)  # polling a log file from the benchmark's own process, not a callback


def _sim_overlay(directory: Path, seed: int) -> Path:
    path = directory / "sim2d_seed.yaml"
    path.write_text(f"sim2d:\n  ros__parameters:\n    seed: {seed}\n")
    return path


def explore(world: str, directory: Path, seed: int, max_time: float, env: dict[str, str]) -> dict[str, float]:
    """Step 1-3 of the module docstring; the map is saved as ``directory/map.yaml``."""
    logs = directory / "logs"
    bringup = _start(["nav-bringup", "--slam", "--world", world, "--rtf", "max", "--participant", "explore",
                      "--sim-params", str(_sim_overlay(directory, seed)), "--log-dir", str(logs)],
                     directory / "bringup_slam.log", env)
    try:
        started = time.monotonic()
        done = subprocess.run([str(BIN / "nav-explore"), "-f", str(directory / "map"), "--max-time",
                               str(max_time)], capture_output=True, text=True, env=env, cwd=REPO,
                              timeout=max_time * 10)
        wall = time.monotonic() - started
    finally:
        _stop(bringup)
    (directory / "explore.log").write_text(done.stdout + done.stderr)
    numbers = progress_numbers(done.stdout)
    timings = [(float(m), float(x)) for m, x in TIMING.findall((logs / "slam.log").read_text())]
    reset = "CRITICAL FAILURE" in (directory / "bringup_slam.log").read_text()
    spawn = load_world(world).spawns[0]
    return {**numbers, "wall_s": wall, "complete": float(done.returncode == 0), "slam_reset": float(reset),
            "iou": compare_with_reference(directory / "map.yaml", REPO / "maps" / f"{world}.yaml", spawn[:2]),
            "scan_median_ms": Stats.of([m for m, _ in timings]).median if timings else float("nan"),
            "scan_max_ms": max((x for _, x in timings), default=float("nan"))}


def navigate(world: str, directory: Path, env: dict[str, str]) -> int:
    """Step 4: AMCL on the saved map, three goals at the world's spawns; how many were reached."""
    spawns = load_world(world).spawns
    goals = [spawns[2], spawns[-2], spawns[-1]] if len(spawns) >= 4 else list(spawns[1:])
    log = directory / "bringup_amcl.log"
    bringup = _start(["nav-bringup", "--world", world, "--map", str(directory / "map.yaml"), "--rtf", "max",
                      "--log-dir", str(directory / "logs_amcl")], log, env)
    reached = 0
    try:
        _wait_ready(bringup, log, timeout=300.0)
        for x, y, yaw in goals:
            done = subprocess.run([str(BIN / "nav-goal"), "goto", str(x), str(y), str(yaw)],
                                  capture_output=True, text=True, env=env, cwd=REPO, timeout=GOAL_TIMEOUT)
            with (directory / "goals.log").open("a") as out:
                out.write(f"goal ({x}, {y}, {yaw}): exit {done.returncode}\n{done.stdout[-600:]}\n")
            reached += done.returncode == 0
    finally:
        _stop(bringup)
    return reached


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--world", default="turtlebot3_house", help="sim2d world (and maps/<world>.yaml)")
    parser.add_argument("--seed", type=int, default=2, help="sim2d noise seed of the first run (default 2)")
    parser.add_argument("--runs", type=int, default=1, help="runs, seeds seed, seed+1, ... (default 1)")
    parser.add_argument("--max-time", type=float, default=1500.0, help="nav-explore --max-time (sim s)")
    parser.add_argument("--note", default="", help="appended to every row's note (e.g. the machine's load)")
    parser.add_argument("--no-record", action="store_true", help="print only; do not append to RESULTS.md")
    args = parser.parse_args()
    domain = str(claim_domain_id())  # held until this process exits
    env = {**os.environ, "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_DOMAIN_ID": domain}
    runs: list[dict[str, float]] = []
    for k in range(args.runs):
        directory = Path(tempfile.mkdtemp(prefix=f"bench_slam_workflow_{args.world}_"))
        run = explore(args.world, directory, args.seed + k, args.max_time, env)
        run["goals_reached"] = float(navigate(args.world, directory, env))
        print(f"run {k + 1} ({directory}): " + ", ".join(f"{key} {value:.4g}" for key, value in run.items()))
        runs.append(run)
    bench = Benchmark("slam_workflow", record_results=not args.no_record)
    note = (f"{args.world}, seeds {args.seed}..{args.seed + args.runs - 1}, "
            f"{sum(r['complete'] for r in runs):.0f}/{len(runs)} explorations complete, "
            f"{sum(r['slam_reset'] for r in runs):.0f} slam resets; {args.note}").rstrip("; ")
    rows = [("exploration duration (sim)", "sim_s", "s"), ("exploration duration (wall)", "wall_s", "s"),
            ("mapped area", "mapped", "m2"), ("occupied IoU vs observable walls (1-cell tol.)", "iou", ""),
            ("slam scan callback, median per 100 scans", "scan_median_ms", "ms"),
            ("slam scan callback, max", "scan_max_ms", "ms"),
            ("NavigateToPose goals reached on the saved map (AMCL), of 3", "goals_reached", "")]
    for metric, key, unit in rows:
        bench.record(f"{args.world}: {metric}", Stats.of([r[key] for r in runs]), unit, note=note)
    bench.save()


if __name__ == "__main__":
    main()
