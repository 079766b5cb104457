"""50 random goals in one world (turtlebot3_world) through the whole stack (nav-bringup), one after another.

By default nav-bringup runs in lockstep at ``--rtf max``: the simulator runs as fast as the stack keeps
up (``--rtf 1`` for real time, ``--no-lockstep`` to let the simulator follow the wall clock alone).

``--world`` and ``--robot`` choose the world (its map maps/<world>.yaml, its first spawn) and the
robot (its parameter file, nav_stack.ros.bringup.robot_params, unless ``--params`` names one); the defaults
are turtlebot3_world and the waffle.

Goals are sampled (seeded) among free map cells with >= 0.4 m clearance to any occupied or unknown
cell, each one reachable per the running planner (compute_path_to_pose from the previous goal;
the plan's length is the optimal path); bench.nav_session runs them. Recorded: success rate,
collisions (sim2d/collision_count delta), time-to-goal against the ideal time (optimal path length
/ the controller's desired_linear_vel in the parameter file: 0.26 m/s for the waffle, 0.30 m/s for
the tb4) three ways: the median and the mean of the per-goal ratios, and the mean time over the mean
ideal (short goals weigh less there: their in-place turns to the path and to the goal's random yaw
are not in the ideal), and the real-time factor the whole stack sustained (sim time / wall time from
the first goal's planning to the last goal's result; the lowest per-goal factor is recorded too).
Also recorded: the navigator's own time (navigation_time of the goal's last feedback) over the ideal,
which leaves out this client's latency (one DDS round trip per goal: a few ms of wall time, i.e.
a few hundredths of a sim second at 7x; the result's sim time is read in the executor thread the
moment it arrives). A plan request the planner does not acknowledge within 5 s (wall) is sent again and
counted ("lost plan requests" in the notes).
Targets: >= 98 % success, 0 collisions, <= 1.3x ideal, a sustained real-time factor >= 5.

    .venv/bin/python -m bench.bench_navigation [--goals 50] [--world turtlebot3_world] [--robot waffle]
                                               [--rtf max] [--no-lockstep] [--seed 7]
                                               [--params FILE] [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import signal
import statistics
import threading
from pathlib import Path

import numpy as np

from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note
from bench.nav_session import (
    MIN_CLEARANCE,
    GoalRecord,
    GoalRun,
    Stack,
    free_poses,
    ideal_speed,
    map_yaml,
    run_goals,
)

DEFAULT_WORLD, DEFAULT_ROBOT = "turtlebot3_world", "waffle"


def _parser() -> argparse.ArgumentParser:
    from nav_stack.ros.bringup.robot_params import ROBOTS

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--goals", type=int, default=50)
    parser.add_argument("--world", default=DEFAULT_WORLD, help="sim2d world (map maps/<world>.yaml)")
    parser.add_argument("--robot", default=DEFAULT_ROBOT, choices=ROBOTS)
    parser.add_argument("--rtf", default="max", help="nav-bringup --rtf (default max: as fast as the "
                        "stack keeps up, in lockstep)")
    parser.add_argument("--no-lockstep", dest="lockstep", action="store_false", default=True,
                        help="nav-bringup --no-lockstep: the simulator follows the wall clock alone")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--params", type=Path, default=None,
                        help="the Nav2 parameter file nav-bringup runs the stack with (default: the robot's)")
    parser.add_argument("--no-record", action="store_true")
    return parser


def _print_goal(record: GoalRecord, goals: int) -> None:
    outcome = record.outcome
    x, y, _ = record.goal
    print(f"goal {record.index:2d}/{goals} ({x:5.2f}, {y:5.2f}): {'ok ' if outcome.ok else 'FAIL'} "
          f"{outcome.sim_s:6.1f} s sim, ideal {record.ideal_s:5.1f} s, ratio {record.ratio:4.2f}, "
          f"navigator {record.navigator_s:5.1f} s, "
          f"recoveries {record.recoveries}, collisions {record.collisions}, "
          f"rtf {outcome.sim_s / max(record.wall_s, 1e-9):.2f} "
          f"(so far {record.sim_so_far / record.wall_so_far:.2f})"
          + ("" if outcome.ok else f" - {outcome.message}"), flush=True)


def _record(bench: Benchmark, run: GoalRun, note: str) -> None:
    done = run.succeeded
    ratios = [record.ratio for record in done]
    ideals = sum(record.ideal_s for record in done)
    bench.record_value("success rate", 100.0 * len(done) / max(len(run.records), 1), "%", note)
    bench.record_value("collisions", float(run.collisions), "count", note)
    if ratios:
        bench.record_value("time-to-goal / ideal (median)", statistics.median(ratios), "x", note)
        bench.record_value("time-to-goal / ideal (mean)", statistics.fmean(ratios), "x", note)
        bench.record_value("mean time-to-goal / mean ideal",
                           sum(record.outcome.sim_s for record in done) / ideals, "x", note)
        bench.record_value("mean navigator time / mean ideal",
                           sum(record.navigator_s for record in done) / ideals, "x",
                           f"{note}; navigation_time of the last feedback (the navigator's own clock), "
                           "to tell the stack's time from this client's latency")
    bench.record_value("sustained real-time factor", run.sim_s / run.wall_s, "x",
                       f"{note}; {run.sim_s:.0f} sim s in {run.wall_s:.0f} wall s")
    if run.goal_rtfs:
        bench.record_value("lowest per-goal real-time factor", min(run.goal_rtfs), "x",
                           f"{note}; median per goal {statistics.median(run.goal_rtfs):.2f}")


def main() -> int:
    from nav_stack.ros.bringup.robot_params import params_for_robot
    from nav_stack.ros.bringup.world_defaults import world_defaults

    args = _parser().parse_args()
    params: Path = args.params or params_for_robot(args.robot)
    domain = enter_local_domain()
    print(f"navigation: ROS_DOMAIN_ID {domain}", flush=True)
    version = code_version_with_fingerprint()
    print(f"navigation: code {version}", flush=True)
    rng = np.random.default_rng(args.seed)
    candidates = free_poses(map_yaml(args.world), MIN_CLEARANCE)
    speed = ideal_speed(params, args.robot)
    start = world_defaults(args.world).spawn[:2]
    bench = Benchmark("navigation")
    interrupted = threading.Event()  # Ctrl-C: finish the current goal, record what was measured
    signal.signal(signal.SIGINT, lambda *_: interrupted.set())
    with Stack(args.world, args.robot, params, args.rtf, args.lockstep) as stack:
        run = run_goals(stack.driver, candidates, rng, start, args.goals, speed,
                        lambda record: _print_goal(record, args.goals), interrupted.is_set)
        default = (args.world, args.robot) == (DEFAULT_WORLD, DEFAULT_ROBOT)
        where = "" if default else f"{args.world}/{args.robot}, "
        note = (f"{where}{len(run.records)}/{args.goals} goals, seed {args.seed}, target rtf {args.rtf}, "
                f"{'lockstep' if args.lockstep else 'no lockstep'}, params {params.name}, "
                f"{version_note(version)}; lost plan requests {run.lost_requests}"
                + (f"; {args.note}" if args.note else ""))
        _record(bench, run, note)
        if not args.no_record:
            bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
