"""SmBatteryPatrol on the simulated battery, repeated: how often does the whole mission succeed?

Each run is the system test's command, ``sm-battery-patrol --rtf max --cycles 2 --low-threshold 0.95
--charged-threshold 0.99`` (sim2d, the Nav2-style stack and the state machine from a cold start; two
patrol rounds with a recharge in each). The demo's own lines decide: ``[patrol] result: SUCCESS``,
``[patrol] visited: a -> b -> ...`` and ``[patrol] rounds R, recharges C, sim S s, wall W s``.

Why: the seed's location3 and station sit 2-4 cm outside a pillar's inflated band, so small
differences in where the robot stops decide whether a turn there is free. A wedge there once failed
one CI run in six; this benchmark counts such failures over many runs, idle and with both cores busy.
Per load group it records the success rate, how many runs visited the locations in the most common
order, and the median wall and sim time of the successful runs.

    .venv/bin/python -m bench.bench_sm_patrol [--runs 10] [--load 0 2] [--robot tb4] [--note TEXT]
                                              [--no-record]
"""

from __future__ import annotations

import argparse
import collections
import re
import sys
from dataclasses import dataclass

from bench.bench_mission import busy_load, load_label, run_mission
from bench.harness import Benchmark, Stats, claim_domain_id, code_version_with_fingerprint, version_note

DEMO_MODULE = "smacc_py.state_machines.sm_battery_patrol.demo"
SUMMARY = re.compile(r"\[patrol\] rounds (\d+), recharges (\d+), sim ([\d.]+) s, wall ([\d.]+) s")
VISITED = re.compile(r"\[patrol\] visited: (.*)")
RESULT = re.compile(r"\[patrol\] result: (.*)")


@dataclass(frozen=True)
class PatrolRun:
    succeeded: bool
    outcome: str  # the demo's result line
    visited: str  # "location1 -> location2 -> station -> ..."
    sim_s: float
    wall_s: float  # the whole command's, bringup included


def patrol_command(python: str = sys.executable, timeout_s: float = 240.0,
                   robot: str | None = None) -> list[str]:
    """The system test's command (tests/system/test_battery_patrol.py), with ``--robot`` if given."""
    return [python, "-m", DEMO_MODULE, "--rtf", "max", "--cycles", "2", "--low-threshold", "0.95",
            "--charged-threshold", "0.99", "--timeout", str(timeout_s),
            *(["--robot", robot] if robot else [])]


def parse_patrol(output: str, wall_s: float) -> PatrolRun:
    """A PatrolRun from the demo's output."""
    result = RESULT.findall(output)
    visited = VISITED.findall(output)
    summary = SUMMARY.search(output)
    outcome = result[-1].strip() if result else "no result line"
    return PatrolRun(outcome.startswith("SUCCESS"), outcome, visited[-1].strip() if visited else "",
                     float(summary.group(3)) if summary else 0.0, wall_s)


def record_group(bench: Benchmark, runs: list[PatrolRun], label: str, note: str) -> None:
    ok = [r for r in runs if r.succeeded]
    orders = collections.Counter(r.visited for r in ok)
    common, same = orders.most_common(1)[0] if orders else ("none", 0)
    failures = " / ".join(sorted({r.outcome for r in runs if not r.succeeded}))[:300]
    group_note = f"{label}: {len(ok)}/{len(runs)} succeeded; {note}"
    bench.record_value(f"sm_battery_patrol success ({label})", 100.0 * len(ok) / len(runs), "%",
                       group_note + (f"; failures: {failures}" if failures else ""))
    bench.record_value(f"sm_battery_patrol runs in the most common visiting order ({label})",
                       100.0 * same / len(runs), "%", f"{same}/{len(runs)}; {len(orders)} orders; "
                                                         f"most common: {common}")
    if ok:
        bench.record(f"sm_battery_patrol wall time ({label})", Stats.of([r.wall_s for r in ok]), "s",
                     note=f"{group_note}; bringup included")
        bench.record(f"sm_battery_patrol sim time ({label})", Stats.of([r.sim_s for r in ok]), "s",
                     note=group_note)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=10, help="runs per load group")
    parser.add_argument("--load", type=int, nargs="+", default=[0, 2],
                        help="busy processes per group (0 = idle)")
    parser.add_argument("--robot", help="sm-battery-patrol --robot (waffle, burger, tb4; default waffle)")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    bench = Benchmark("patrol")
    started = code_version_with_fingerprint()
    domain = claim_domain_id()
    groups: dict[str, list[PatrolRun]] = {}
    for load in args.load:
        label = load_label(load) + (f", robot {args.robot}" if args.robot else "")
        with busy_load(load):
            runs = []
            for index in range(args.runs):
                mission = run_mission(patrol_command(robot=args.robot), domain)
                run = parse_patrol(mission.output, mission.wall_s)
                runs.append(run)
                print(f"patrol ({label}) {index + 1}/{args.runs}: {'ok  ' if run.succeeded else 'FAIL'} "
                      f"wall {run.wall_s:5.1f} s, sim {run.sim_s:6.1f} s - {run.outcome}", flush=True)
                if not run.succeeded:
                    print("\n".join(mission.output.splitlines()[-30:]), flush=True)
        groups[label] = runs
    note = version_note(started) + (f"; {args.note}" if args.note else "")
    for label, runs in groups.items():
        record_group(bench, runs, label, note)
    bench.save()
    return 0 if all(r.succeeded for runs in groups.values() for r in runs) else 1


if __name__ == "__main__":
    raise SystemExit(main())
