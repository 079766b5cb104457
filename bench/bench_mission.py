"""The whole seed mission (make demo), in lockstep at --rtf max by default, idle and under CPU load.

Each run is ``navsuite-demo --rtf R --quiet --no-report``: sim2d, the Nav2-style stack and
SmNav2Test1 from a cold start, through initial pose, two waypoints and the spin. The demo's own output
decides everything: its ``result:`` line (success), its transition lines ``[demo] [t=20.68 s] StA ->
StB [TAG] on EvX[...]`` (the state sequence, source->target) and its summary line (the mission's sim
time and the real-time factor it reached: sim time over the mission's own wall time, from the
machine's start). The wall time recorded is the whole command's, bringup included.

Load groups: ``--load 0 2`` (the default) runs the mission ``--runs`` times idle, then ``--runs``
times while 2 busy processes (``python -c "while True: pass"``, nice 0, started and killed by this
benchmark) load both cores. Per group it records the success rate, how many runs followed the
reference state sequence (the most common one of the first group's successful runs), the median
wall time, the median sim time and the real-time factor (median, min, max over the runs).

A second real-time factor is measured here: sim time over wall time from the first transition to the
last (wall = when each transition line arrives), i.e. the mission without StAllSensorsGo, whose sim
length follows DDS discovery in wall time while the simulator already runs.

The old wall-clock comparison stays possible: ``--rtf 1 2 --no-lockstep`` runs nav-bringup with
``--no-lockstep`` (through the demo's ``--bringup`` option) at those factors.

    .venv/bin/python -m bench.bench_mission [--rtf max] [--runs 10] [--load 0 2] [--no-lockstep]
                                            [--robot tb4] [--waypoint2 0,0,0] [--note TEXT] [--no-record]

``--waypoint2 0,0,0`` measures upstream's second waypoint, inside the middle pillar, which NavFn's
goal tolerance turns into the nearest reachable point (the README's "NavFn goal tolerance" row).
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import shlex
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from bench.harness import Benchmark, Stats, claim_domain_id, code_version_with_fingerprint, version_note

REPO = Path(__file__).resolve().parents[1]
RUN_TIMEOUT = 900.0  # s (wall) per mission, bringup included (the demo's own limit is 600 s)
DEMO_MODULE = "smacc_py.state_machines.sm_nav2_test_1.demo"
SUMMARY = re.compile(r"transitions: (\d+); sim time ([\d.]+) s; wall time ([\d.]+) s"
                     r"(?:; real-time factor ([\d.]+))?")
TRANSITION = re.compile(r"\[demo\] \[t=([\d.]+) s\] (\w+) -> (\w+) \[(\w+)\] on (\S+)")


@dataclass(frozen=True)
class Run:
    succeeded: bool
    wall_s: float  # whole command, bringup included (measured here)
    sim_s: float  # the state machine's run, as the demo reports it
    rtf: float | None  # the demo's "real-time factor" (mission sim time / mission wall time)
    sequence: tuple[str, ...]  # "source->target" per transition, in order
    outcome: str  # the demo's result line
    output: str = ""
    stamps: tuple[float, ...] = ()  # sim time (s) of each transition
    wall_stamps: tuple[float, ...] = ()  # wall s (from the command's start) each transition line arrived

    @property
    def transit_rtf(self) -> float | None:
        """Sim time over wall time from the first transition to the last (the lines' arrival times):
        the mission without StAllSensorsGo, whose length depends on DDS discovery in wall time."""
        if len(self.stamps) < 2 or len(self.wall_stamps) != len(self.stamps):
            return None
        wall = self.wall_stamps[-1] - self.wall_stamps[0]
        return (self.stamps[-1] - self.stamps[0]) / wall if wall > 0.0 else None

    def timeline(self) -> str:
        """``StA->StB@3.40, ...``: the sequence with each transition's sim time."""
        return ", ".join(f"{step}@{t:.2f}" for step, t in zip(self.sequence, self.stamps, strict=False))

    def describe(self) -> str:
        rtf = f"{self.rtf:5.1f}" if self.rtf is not None else "  n/a"
        transit = f"{self.transit_rtf:5.1f}" if self.transit_rtf is not None else "  n/a"
        return (f"{'ok  ' if self.succeeded else 'FAIL'} wall {self.wall_s:6.1f} s, sim {self.sim_s:6.1f} s, "
                f"rtf {rtf} (first to last transition {transit}) - {self.outcome}")


def demo_command(rtf: str, lockstep: bool = True, python: str = sys.executable,
                 robot: str | None = None, waypoint2: str | None = None) -> list[str]:
    """``navsuite-demo --rtf R --quiet --no-report [--robot NAME] [--waypoint2 X,Y,YAW]``; without
    lockstep nav-bringup gets ``--no-lockstep``."""
    command = [python, "-m", DEMO_MODULE, "--rtf", rtf, "--quiet", "--no-report"]
    if robot:
        command += ["--robot", robot]
    if waypoint2:
        command += ["--waypoint2", waypoint2]
    if not lockstep:
        command += ["--bringup", f"{shlex.quote(python)} -m nav_stack.ros.bringup.nav_bringup --no-lockstep"]
    return command


def parse_run(output: str, returncode: int | None, wall_s: float,
              line_times: Sequence[tuple[float, str]] = ()) -> Run:
    """A Run from the demo's output: success from its result line, sequence from its transition lines."""
    summary = SUMMARY.search(output)
    results = [line.split("result:", 1)[1].strip() for line in output.splitlines()
               if "[demo] result:" in line]
    outcome = results[-1] if results else f"no result line (exit {returncode})"
    sequence = tuple(f"{m.group(2)}->{m.group(3)}" for m in TRANSITION.finditer(output))
    succeeded = returncode == 0 and outcome.startswith("SUCCESS")
    sim_s = float(summary.group(2)) if summary else 0.0
    rtf = float(summary.group(4)) if summary and summary.group(4) else None
    stamps = tuple(float(m.group(1)) for m in TRANSITION.finditer(output))
    wall_stamps = tuple(t for t, line in line_times if TRANSITION.search(line))
    return Run(succeeded, wall_s, sim_s, rtf, sequence, outcome, output, stamps, wall_stamps)


def run_mission(command: Sequence[str], domain: int, cwd: Path = REPO,
                env_extra: dict[str, str] | None = None) -> Run:
    """One cold-start mission; the demo's own output decides success. Lines are read as they arrive,
    so each transition line also gets a wall time."""
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), **(env_extra or {}))
    env.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    started = time.monotonic()
    proc = subprocess.Popen(list(command), cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, bufsize=1)
    line_times: list[tuple[float, str]] = []

    def read() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            line_times.append((time.monotonic() - started, line))

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        proc.wait(timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        reader.join(timeout=10.0)
        return Run(False, time.monotonic() - started, 0.0, None, (), f"timeout after {RUN_TIMEOUT:.0f} s",
                   "".join(line for _, line in line_times))
    wall = time.monotonic() - started
    reader.join(timeout=10.0)
    return parse_run("".join(line for _, line in line_times), proc.returncode, wall, line_times)


@contextmanager
def busy_load(count: int) -> Iterator[list[subprocess.Popen[bytes]]]:
    """``count`` busy-loop processes (``python -c "while True: pass"``, nice 0) for the block's duration."""
    procs: list[subprocess.Popen[bytes]] = []
    try:
        for _ in range(count):
            procs.append(subprocess.Popen([sys.executable, "-c", "while True: pass"],
                                          preexec_fn=lambda: os.setpriority(os.PRIO_PROCESS, 0, 0)))
        for proc in procs:
            print(f"mission: busy process pid {proc.pid}, nice {os.getpriority(os.PRIO_PROCESS, proc.pid)}",
                  flush=True)
        yield procs
    finally:
        for proc in procs:
            proc.kill()
        for proc in procs:
            proc.wait(timeout=10.0)


def load_label(count: int) -> str:
    return "idle" if count == 0 else f"{count} busy process{'es' if count > 1 else ''}"


def record_group(bench: Benchmark, runs: list[Run], label: str, reference: tuple[str, ...] | None,
                 extra_note: str) -> None:
    ok = [r for r in runs if r.succeeded]
    same = sum(1 for r in runs if reference is not None and r.sequence == reference)
    identical = len({r.sequence for r in runs}) == 1
    note = f"{label}: {len(ok)}/{len(runs)} succeeded" + (f"; {extra_note}" if extra_note else "")
    failures = sorted({r.outcome for r in runs if not r.succeeded})
    bench.record_value(f"seed mission success ({label})", 100.0 * len(ok) / len(runs), "%",
                       note + (f"; failures: {' / '.join(failures)}"[:400] if failures else ""))
    bench.record_value(f"seed mission runs with the reference state sequence ({label})",
                       100.0 * same / len(runs), "%",
                       f"{same}/{len(runs)}; all runs identical: {'yes' if identical else 'no'}; "
                       f"reference: {', '.join(reference) if reference else 'none'}")
    if ok:
        bench.record(f"seed mission wall time ({label})", Stats.of([r.wall_s for r in ok]), "s",
                     note=f"{note}; bringup included")
        bench.record(f"seed mission sim time ({label})", Stats.of([r.sim_s for r in ok]), "s", note=note)
        rtfs = [r.rtf for r in ok if r.rtf is not None]
        if rtfs:
            bench.record(f"seed mission real-time factor ({label})", Stats.of(rtfs), "x",
                         note=f"{note}; the demo's figure: mission sim time / mission wall time; "
                              f"min = slowest run")
        transit = [r.transit_rtf for r in ok if r.transit_rtf is not None]
        if transit:
            bench.record(f"seed mission real-time factor, first to last transition ({label})",
                         Stats.of(transit), "x",
                         note=f"{note}; without StAllSensorsGo (its sim length follows DDS discovery "
                              f"in wall time); wall = arrival of the transition lines; min = slowest run")
    for run in runs:
        if not run.succeeded:  # show why (the demo prints the stack's last lines when it fails)
            print(f"--- {label}: output of a failed run (last 40 lines) ---", flush=True)
            print("\n".join(run.output.splitlines()[-40:]), flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rtf", nargs="+", default=["max"], help="real-time factors ('max' = lockstep max)")
    parser.add_argument("--runs", type=int, default=10, help="runs per factor and load group")
    parser.add_argument("--load", type=int, nargs="+", default=[0, 2],
                        help="busy processes per group (default: 0 then 2: idle, then both cores loaded)")
    parser.add_argument("--no-lockstep", dest="lockstep", action="store_false", default=True,
                        help="nav-bringup --no-lockstep: the simulator follows the wall clock")
    parser.add_argument("--robot", help="navsuite-demo --robot (waffle, burger, tb4; default waffle)")
    parser.add_argument("--waypoint2", help="navsuite-demo --waypoint2 X,Y,YAW (e.g. 0,0,0: inside a pillar)")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    bench = Benchmark("mission")  # --no-record is read by the harness
    domain = claim_domain_id()
    version = code_version_with_fingerprint()
    print(f"mission: ROS_DOMAIN_ID {domain}; code {version}", flush=True)
    summary: list[str] = []
    for rtf in args.rtf:
        mode = f"rtf {rtf}, {'lockstep' if args.lockstep else 'no lockstep'}"
        if args.robot:
            mode += f", robot {args.robot}"
        if args.waypoint2:
            mode += f", waypoint2 {args.waypoint2}"
        command = demo_command(rtf, args.lockstep, robot=args.robot, waypoint2=args.waypoint2)
        print(f"mission: {' '.join(shlex.quote(c) for c in command)}", flush=True)
        reference: tuple[str, ...] | None = None
        sequences_seen: set[tuple[str, ...]] = set()
        for load in args.load:
            label = f"{mode}, {load_label(load)}"
            runs: list[Run] = []
            with busy_load(load):
                for index in range(args.runs):
                    run = run_mission(command, domain)
                    runs.append(run)
                    print(f"{label} run {index + 1}/{args.runs}: {run.describe()}", flush=True)
                    print(f"    sequence (sim s): {run.timeline() or '(none)'}", flush=True)
            if reference is None:
                common = collections.Counter(r.sequence for r in runs if r.succeeded).most_common(1)
                reference = common[0][0] if common else None
            sequences_seen |= {r.sequence for r in runs}
            record_group(bench, runs, label, reference,
                         "; ".join(n for n in (version_note(version), args.note) if n))
            ok = [r for r in runs if r.succeeded]
            rtfs = [r.rtf for r in ok if r.rtf is not None]
            transit = [r.transit_rtf for r in ok if r.transit_rtf is not None]
            summary.append(
                f"{label}: {len(ok)}/{len(runs)} SUCCESS; identical sequence in all runs: "
                f"{'yes' if len({r.sequence for r in runs}) == 1 else 'no'}; "
                f"reference sequence: {sum(r.sequence == reference for r in runs)}/{len(runs)}; "
                + (f"median wall {statistics.median(r.wall_s for r in ok):.1f} s, median sim "
                   f"{statistics.median(r.sim_s for r in ok):.1f} s" if ok else "no success")
                + (f", rtf median {statistics.median(rtfs):.1f} (min {min(rtfs):.1f}, max {max(rtfs):.1f})"
                   if rtfs else "")
                + (f", first-to-last-transition rtf median {statistics.median(transit):.1f} "
                   f"(min {min(transit):.1f}, max {max(transit):.1f})" if transit else ""))
        summary.append(f"{mode}: one state sequence across every load group: "
                       f"{'yes' if len(sequences_seen) == 1 else f'no ({len(sequences_seen)} distinct)'}")
    print("mission: ---------------- summary ----------------", flush=True)
    for line in summary:
        print(f"mission: {line}", flush=True)
    bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
