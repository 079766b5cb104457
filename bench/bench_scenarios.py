"""Scenario farm throughput: the shipped scenario file with 1 worker, then 2; scenarios per hour, speed-up.

Each pass is one ``navsuite-scenarios run`` (a subprocess, as a user runs it) into a fresh directory;
its wall time includes every bringup, run, report and shutdown. The verdicts of the passes are compared
scenario by scenario: lockstep runs must not depend on how many run at once, so a difference is
printed as a finding. Speed-up is the 1-worker wall time over the N-worker one (ideal: N on N free cores).

Usage::

    .venv/bin/python -m bench.bench_scenarios                      # shipped file, --workers 1 then 2
    .venv/bin/python -m bench.bench_scenarios -k seed_ --workers 1 2 --no-record
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench.harness import Benchmark, code_version_with_fingerprint, version_note
from navsuite_tools.scenarios.farm import injected_events
from navsuite_tools.scenarios.schema import load_scenarios
from navsuite_tools.scenarios.verdict import Outcome, judge

REPO = Path(__file__).resolve().parents[1]
SHIPPED = REPO / "config" / "scenarios" / "seed_missions.yaml"


def run_pass(file: Path, workers: int, selection: list[str], out: Path,
             domains: str | None) -> tuple[float, dict[str, bool], int]:
    """One farm run: (wall s, scenario → passed, exit code)."""
    command = [sys.executable, "-m", "navsuite_tools.scenarios.main", "run", str(file),
               "--workers", str(workers), "--out", str(out),
               *(arg for name in selection for arg in ("-k", name)),
               *(["--domains", domains] if domains else [])]
    started = time.monotonic()
    proc = subprocess.run(command, cwd=REPO, capture_output=True, text=True)
    wall = time.monotonic() - started
    print(proc.stdout.rstrip(), flush=True)
    if proc.returncode not in (0, 1):
        print(proc.stderr.rstrip(), file=sys.stderr, flush=True)
    scenarios = {s.name: s for s in load_scenarios(file, REPO / "config")}
    passed = {}
    for result in sorted(out.glob("*/result.json")):
        outcome = Outcome.from_json(json.loads(result.read_text()))
        scenario = scenarios[result.parent.name]
        passed[scenario.name] = judge(scenario.expect, outcome, injected_events(scenario)).passed
    return wall, passed, proc.returncode


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--file", type=Path, default=SHIPPED, help="scenario file (default: the shipped one)")
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2],
                        help="worker counts, the first is the baseline")
    parser.add_argument("-k", dest="select", action="append", default=[], help="as navsuite-scenarios -k")
    parser.add_argument("--domains", help="as navsuite-scenarios --domains")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    bench = Benchmark("scenarios")  # --no-record is read by the harness
    version = code_version_with_fingerprint()
    note = "; ".join(n for n in (version_note(version), args.file.name, args.note) if n)
    results: dict[int, tuple[float, dict[str, bool]]] = {}
    with tempfile.TemporaryDirectory(prefix="bench-scenarios-") as tmp:
        for workers in args.workers:
            out = Path(tmp) / f"w{workers}"
            wall, passed, code = run_pass(args.file, workers, args.select, out, args.domains)
            results[workers] = (wall, passed)
            rate = len(passed) / wall * 3600.0
            print(f"scenarios: --workers {workers}: {len(passed)} scenarios, {sum(passed.values())} passed, "
                  f"wall {wall:.0f} s, {rate:.0f} scenarios/h (exit {code})", flush=True)
            counts = f"{len(passed)} scenarios, {sum(passed.values())} passed, wall {wall:.0f} s"
            bench.record_value(f"scenarios per hour, --workers {workers}", rate, "1/h", f"{counts}; {note}")
    base_workers = args.workers[0]
    base_wall, base_passed = results[base_workers]
    for workers in args.workers[1:]:
        wall, passed = results[workers]
        bench.record_value(f"speed-up --workers {workers} vs {base_workers}", base_wall / wall, "x", note)
        differ = sorted(name for name in base_passed if passed.get(name) != base_passed[name])
        print(f"scenarios: verdicts with --workers {workers} vs {base_workers}: "
              + ("identical" if not differ else f"DIFFERENT for {', '.join(differ)}"), flush=True)
    bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
