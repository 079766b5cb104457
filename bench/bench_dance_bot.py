"""sm_dance_bot's whole run, repeated: wall time, sim time and number of transitions (medians).

Each run is the system test's command, ``python -m smacc_py.state_machines.sm_dance_bot.demo --rtf max``
(sim2d, the Nav2-style stack, the support nodes and SmDanceBot from a cold start, in lockstep; the
scripted overheating takes the machine through its recovery mode once). The demo's own output decides
(bench.bench_mission.run_mission parses it): its ``result:`` line, its transition lines and its summary
line (sim time of the machine's run). The wall time is the whole command's, bringup included.

    .venv/bin/python -m bench.bench_dance_bot [--runs 3] [--domain ID] [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import sys

from bench.bench_mission import run_mission
from bench.harness import Benchmark, Stats, claim_domain_id, code_version_with_fingerprint, version_note

DEMO_MODULE = "smacc_py.state_machines.sm_dance_bot.demo"


def dance_command(python: str = sys.executable, timeout_s: float = 780.0) -> list[str]:
    """The system test's command (tests/system/test_sm_dance_bot.py)."""
    return [python, "-m", DEMO_MODULE, "--rtf", "max", "--timeout", str(timeout_s)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs (cold starts)")
    parser.add_argument("--domain", type=int, help="ROS_DOMAIN_ID (default: one no test session holds)")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    bench = Benchmark("dance_bot")
    started = code_version_with_fingerprint()
    domain = args.domain if args.domain is not None else claim_domain_id()
    runs = []
    for index in range(args.runs):
        run = run_mission(dance_command(), domain)
        runs.append(run)
        verdict = "ok  " if run.succeeded else "FAIL"
        print(f"dance_bot {index + 1}/{args.runs}: {verdict} wall {run.wall_s:6.1f} s, "
              f"sim {run.sim_s:6.1f} s, {len(run.sequence)} transitions - {run.outcome}", flush=True)
        if not run.succeeded:
            print("\n".join(run.output.splitlines()[-30:]), flush=True)
    ok = [r for r in runs if r.succeeded]
    note = f"{len(ok)}/{len(runs)} succeeded; {version_note(started)}"
    note += f"; {args.note}" if args.note else ""
    bench.record_value("sm_dance_bot success", 100.0 * len(ok) / len(runs), "%", note)
    if ok:
        bench.record("sm_dance_bot wall time", Stats.of([r.wall_s for r in ok]), "s",
                     note=f"{note}; bringup included")
        bench.record("sm_dance_bot sim time", Stats.of([r.sim_s for r in ok]), "s", note=note)
        bench.record("sm_dance_bot transitions", Stats.of([float(len(r.sequence)) for r in ok]), "",
                     note=note)
    bench.save()
    return 0 if len(ok) == len(runs) else 1


if __name__ == "__main__":
    raise SystemExit(main())
