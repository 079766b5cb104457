"""Soak: 200 random goals over four worlds and two robots, one whole stack (nav-bringup) per world.

The default plan is turtlebot3_world and turtlebot3_house with the waffle, the generated
office_small and depot_large with the tb4, 50 goals each (``--goals N`` splits N over those four;
``--plan world:robot:goals,...`` names another plan). Each configuration starts its own stack in
lockstep at ``--rtf max`` and drives its goals exactly as bench_navigation does (bench.nav_session:
seeded free goals with 0.4 m clearance, reachable per the planner).

Recorded per configuration and in total: success rate; collisions (sim2d/collision_count delta);
failures split into explained (a result with a non-zero error_code and an error_msg) and
unexplained (error_code 0 or an empty message, or no result at all: not accepted, timed out, or a
configuration that ended early, whose missing goals count here); the battery's charge at the end
(/battery_state; it must never reach 0); the resident memory (VmRSS, MiB) of every process of the
stack after the first goal (warm; ``--warm-after N``: after goal N) and at the end, with the growth
in %; the median time-to-goal over the ideal and the median wall time per goal. Every failure
prints its error_msg.
Targets: >= 98 % success, 0 collisions, 0 unexplained failures, memory growth < 10 %, the battery
never empty.

    .venv/bin/python -m bench.bench_soak [--goals 200 | --plan world:robot:goals,...] [--rtf max]
                                         [--no-lockstep] [--seed 7] [--warm-after 1] [--note TEXT]
                                         [--no-record]
"""

from __future__ import annotations

import argparse
import signal
import threading

import numpy as np

from bench.harness import Benchmark, code_version_with_fingerprint, enter_local_domain, version_note
from bench.nav_session import MIN_CLEARANCE, GoalRecord, Stack, free_poses, ideal_speed, map_yaml, run_goals
from bench.proc_memory import compare, tree_memory
from bench.soak_report import Config, ConfigResult, parse_plan, print_summary, record, split_goals

DEFAULT_CONFIGS = (("turtlebot3_world", "waffle"), ("turtlebot3_house", "waffle"),
                   ("office_small", "tb4"), ("depot_large", "tb4"))


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--goals", type=int, default=200,
                        help="goals split evenly over the default plan's four configurations")
    parser.add_argument("--plan", default=None, metavar="WORLD:ROBOT:GOALS,...",
                        help="the configurations and their goals instead (e.g. turtlebot3_house:waffle:3)")
    parser.add_argument("--rtf", default="max", help="nav-bringup --rtf (default max, in lockstep)")
    parser.add_argument("--no-lockstep", dest="lockstep", action="store_false", default=True,
                        help="nav-bringup --no-lockstep: the simulator follows the wall clock alone")
    parser.add_argument("--seed", type=int, default=7, help="configuration i draws its goals with seed + i")
    parser.add_argument("--warm-after", type=int, default=1, metavar="N",
                        help="read the warm memory after goal N of each configuration (default 1)")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    return parser


def _plan(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[Config]:
    try:
        if args.warm_after < 1:
            raise ValueError(f"--warm-after must be at least 1, got {args.warm_after}")
        if args.plan is not None:
            return parse_plan(args.plan)
        counts = split_goals(args.goals, len(DEFAULT_CONFIGS))
        return [Config(world, robot, goals)
                for (world, robot), goals in zip(DEFAULT_CONFIGS, counts, strict=True) if goals > 0]
    except ValueError as error:
        parser.error(str(error))


def _print_goal(record: GoalRecord, config: Config, done_before: int, total: int) -> None:
    outcome = record.outcome
    result = "ok  " if outcome.ok else "FAIL"
    failure = "" if outcome.ok else (f" - {'explained' if outcome.explained else 'UNEXPLAINED'} "
                                     f"(error_code {outcome.code}): {outcome.message or '(no error_msg)'}")
    print(f"soak {done_before + record.index:3d}/{total} {config.world}/{config.robot} "
          f"{record.index:2d}/{config.goals}: {result} {outcome.sim_s:6.1f} s sim "
          f"(ideal {record.ideal_s:5.1f} s), {record.wall_s:5.1f} s wall, "
          f"collisions {record.collisions}" + failure, flush=True)


def run_config(config: Config, seed: int, args: argparse.Namespace, done_before: int, total: int,
               stop: threading.Event) -> ConfigResult:
    """Start a stack for ``config``, drive its goals, read memory and battery; stop the stack."""
    from nav_stack.ros.bringup.robot_params import params_for_robot
    from nav_stack.ros.bringup.world_defaults import world_defaults

    params = params_for_robot(config.robot)
    result = ConfigResult(config)
    try:
        candidates = free_poses(map_yaml(config.world), MIN_CLEARANCE)
        speed = ideal_speed(params, config.robot)
        start = world_defaults(config.world).spawn[:2]
        rng = np.random.default_rng(seed)
        with Stack(config.world, config.robot, params, args.rtf, args.lockstep, "bench_soak") as stack:
            assert stack.process is not None
            root = stack.process.pid
            warm: dict[str, float] = {}

            def on_goal(record: GoalRecord) -> None:  # kept as they come: an early end keeps them
                result.records.append(record)
                result.collisions = record.collisions
                result.battery = stack.driver.battery
                _print_goal(record, config, done_before, total)
                if record.index == min(args.warm_after, config.goals):
                    warm.update(tree_memory(root))

            run = run_goals(stack.driver, candidates, rng, start, config.goals, speed, on_goal, stop.is_set)
            result.collisions = run.collisions
            result.battery = stack.driver.battery
            result.memory = compare(warm, tree_memory(root))
    except Exception as error:  # the next configurations still run; the error is reported
        result.error = f"{type(error).__name__}: {error}"
        print(f"soak: {config.world}/{config.robot} ended early: {result.error}", flush=True)
    return result


def main() -> int:
    parser = _parser()
    args = parser.parse_args()
    plan = _plan(args, parser)
    domain = enter_local_domain()
    print(f"soak: ROS_DOMAIN_ID {domain}", flush=True)
    version = code_version_with_fingerprint()
    print(f"soak: code {version}; plan {', '.join(str(config) for config in plan)}", flush=True)
    interrupted = threading.Event()  # Ctrl-C: finish the current goal, record what was measured
    signal.signal(signal.SIGINT, lambda *_: interrupted.set())
    total = sum(config.goals for config in plan)
    results: list[ConfigResult] = []
    for index, config in enumerate(plan):
        results.append(run_config(config, args.seed + index, args, sum(c.goals for c in plan[:index]), total,
                                  interrupted))
        if interrupted.is_set():
            break
    print_summary(results)
    note = (f"seed {args.seed}, target rtf {args.rtf}, {'lockstep' if args.lockstep else 'no lockstep'}, "
            f"warm memory after goal {args.warm_after}, {version_note(version)}"
            + (f"; {args.note}" if args.note else ""))
    bench = Benchmark("soak")
    record(bench, results, note)
    if not args.no_record:
        bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

