"""CPU seconds per simulated second, per process, for the seed mission: before (3839f80) and after.

"After" is this checkout's ``navsuite-demo --rtf max --quiet --no-report`` (lockstep, one ``nav2``
process). "Before" is the same mission run by the code of commit 3839f80 (``--rtf 1``, its default;
it has no lockstep; localization and navigation are two processes there): a ``git worktree`` of that
commit in /tmp/navsuite_before, run with this venv's Python, with cwd and PYTHONPATH set to the
worktree (the venv's editable install points at this checkout, so PYTHONPATH must come first; the
benchmark checks where every package is imported from before it runs, and checks each sampled
process's PYTHONPATH). The worktree is removed at the end.

While a demo runs, every descendant process (the demo itself, which runs the state machine; the
nav-bringup launcher; sim2d; the nav2 process, or localization + navigation; the initial-pose
publisher) is sampled every 0.2 s from /proc/<pid>/stat (utime + stime, the process's own threads,
not its children), keeping the last sample per pid; processes are named by their command line. The
figure is CPU seconds over the mission's sim time (the demo's summary line):

* ``whole run``: all the CPU the process used, bringup included;
* ``mission``: only what it used from the demo's ``[demo] mission:`` line (the stack is up) to its exit;
* ``first to last transition``: what it used between the first and the last transition line, over the
  sim time between those transitions. This leaves out StAllSensorsGo, whose sim length varies from run to
  run after the change (DDS discovery in wall time while the simulator runs), so it compares like with
  like.

Runs alternate before/after (``--runs`` each, default 3) so both see the same machine; the tables
show the median per process, and the ratio after / before. Recorded in RESULTS.md: ``whole run`` and
``first to last transition`` (``mission`` is printed only).

    .venv/bin/python -m bench.bench_cpu [--runs 3] [--before-commit 3839f80] [--keep-worktree]
                                        [--note TEXT] [--no-record]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from bench.bench_mission import DEMO_MODULE, TRANSITION, Run, demo_command, parse_run
from bench.harness import Benchmark, claim_domain_id, code_version_with_fingerprint, version_note

REPO = Path(__file__).resolve().parents[1]
WORKTREE = Path("/tmp/navsuite_before")
BEFORE_COMMIT = "3839f80"
POLL_S = 0.2
RUN_TIMEOUT = 900.0  # s (wall)
TICK = os.sysconf("SC_CLK_TCK")
PACKAGES = ("smacc_py", "nav_stack", "sim2d", "ros_tools")
MISSION_LINE = "[demo] mission:"

#: (substring of the command line, process name), first match wins
PROCESS_NAMES = (
    (DEMO_MODULE, "demo (state machine)"),
    ("bringup component all", "nav2 (all nodes)"),
    ("bringup component localization", "localization"),
    ("bringup component navigation", "navigation"),
    ("sim2d.ros.cli", "sim2d"),
    ("initial_pose_publisher", "initial_pose"),
    ("navsuite_tools.bag", "recorder"),
    ("nav_stack.ros.bringup.nav_bringup", "nav-bringup (launcher)"),
    ("nav-bringup", "nav-bringup (launcher)"),
)
#: the Nav2 node processes, summed as one row (one process after, two before)
NAV_NODES = ("nav2 (all nodes)", "localization", "navigation")


def process_name(cmdline: str) -> str:
    for needle, name in PROCESS_NAMES:
        if needle in cmdline:
            return name
    return Path(cmdline.split(" ", 1)[0]).name or "?"


def _read_stat(pid: int) -> tuple[int, float] | None:
    """(ppid, utime + stime in s) of ``pid``; None when it is gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text.rsplit(")", 1)[1].split()  # after "(comm)", which may contain spaces
    return int(fields[1]), (int(fields[11]) + int(fields[12])) / TICK


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
    except OSError:
        return ""


def _pythonpath(pid: int) -> str | None:
    try:
        for item in Path(f"/proc/{pid}/environ").read_bytes().split(b"\0"):
            if item.startswith(b"PYTHONPATH="):
                return item.split(b"=", 1)[1].decode()
    except OSError:
        return None
    return ""


@dataclass
class Sampler:
    """Last CPU sample per descendant pid of ``root``, plus named snapshots taken on demand."""

    root: int
    last: dict[int, tuple[str, float]] = field(default_factory=dict)  # pid -> (cmdline, cpu s)
    snapshots: dict[str, dict[int, float]] = field(default_factory=dict)  # name -> pid -> cpu s
    pythonpaths: dict[int, str | None] = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def sample(self) -> None:
        stats: dict[int, tuple[int, float]] = {}
        for entry in os.scandir("/proc"):
            if entry.name.isdigit():
                stat = _read_stat(int(entry.name))
                if stat is not None:
                    stats[int(entry.name)] = stat
        family = {self.root}
        grew = True
        while grew:  # descendants: children of any member, to any depth
            grew = False
            for pid, (ppid, _) in stats.items():
                if ppid in family and pid not in family:
                    family.add(pid)
                    grew = True
        with self.lock:
            for pid in family:
                if pid not in stats:
                    continue
                if pid not in self.last:
                    cmdline = _cmdline(pid)
                    if not cmdline:
                        continue
                    self.pythonpaths[pid] = _pythonpath(pid)
                else:
                    cmdline = self.last[pid][0]
                self.last[pid] = (cmdline, stats[pid][1])

    def snapshot(self, name: str, replace: bool = False) -> None:
        """Sample now and keep the CPU of every pid seen so far (exited ones at their last value) under
        ``name``; without ``replace`` only the first snapshot of a name is kept."""
        if name in self.snapshots and not replace:
            return
        self.sample()
        with self.lock:
            self.snapshots[name] = {pid: cpu for pid, (_, cpu) in self.last.items()}


@dataclass
class CpuRun:
    run: Run
    whole: dict[str, float]  # process name -> CPU s (summed over pids of that name)
    mission: dict[str, float]  # from the "[demo] mission:" line to the exit
    transit: dict[str, float]  # from the first transition line to the last
    pythonpaths: set[str | None]

    def sim_s(self, part: str) -> float:
        """The sim seconds a part's CPU is divided by."""
        if part == "transit":
            return self.run.stamps[-1] - self.run.stamps[0]
        return self.run.sim_s


def run_sampled(command: Sequence[str], cwd: Path, env: dict[str, str]) -> CpuRun:
    """Run one demo, sampling its process tree every POLL_S until it exits."""
    started = time.monotonic()
    proc = subprocess.Popen(list(command), cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, bufsize=1)
    sampler = Sampler(proc.pid)
    lines: list[tuple[float, str]] = []

    def read() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            lines.append((time.monotonic() - started, line))
            if line.startswith(MISSION_LINE):
                sampler.snapshot("mission")
            if TRANSITION.search(line):
                sampler.snapshot("first transition")
                sampler.snapshot("last transition", replace=True)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    while proc.poll() is None:
        sampler.sample()
        if time.monotonic() - started > RUN_TIMEOUT:
            proc.kill()
            break
        time.sleep(POLL_S)
    proc.wait()
    reader.join(timeout=10.0)
    run = parse_run("".join(line for _, line in lines), proc.returncode, time.monotonic() - started, lines)
    whole: dict[str, float] = {}
    mission: dict[str, float] = {}
    transit: dict[str, float] = {}
    at_mission = sampler.snapshots.get("mission", {})
    first = sampler.snapshots.get("first transition", {})
    last = sampler.snapshots.get("last transition", {})
    for pid, (cmdline, cpu) in sampler.last.items():
        name = process_name(cmdline)
        whole[name] = whole.get(name, 0.0) + cpu
        mission[name] = mission.get(name, 0.0) + cpu - at_mission.get(pid, 0.0)
        transit[name] = transit.get(name, 0.0) + last.get(pid, 0.0) - first.get(pid, 0.0)
    return CpuRun(run, whole, mission, transit, set(sampler.pythonpaths.values()))


# ------------------------------------------------------------------ the "before" checkout
def create_worktree(commit: str) -> None:
    if WORKTREE.exists():
        raise SystemExit(f"{WORKTREE} exists already: remove it (git worktree remove --force {WORKTREE})")
    subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(WORKTREE), commit], check=True)


def remove_worktree() -> None:
    subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(WORKTREE)], check=False)


def before_env(base: dict[str, str]) -> dict[str, str]:
    previous = base.get("PYTHONPATH")
    return dict(base, PYTHONPATH=str(WORKTREE) + (os.pathsep + previous if previous else ""))


def verify_imports(env: dict[str, str], cwd: Path, root: Path) -> None:
    """Fail unless every package (and the demo and bringup modules) is imported from ``root``."""
    modules = [*PACKAGES, DEMO_MODULE, "nav_stack.ros.bringup.nav_bringup", "sim2d.ros.cli"]
    code = "import importlib\n" + "".join(
        f"print(importlib.import_module({m!r}).__file__)\n" for m in modules)
    out = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True, text=True,
                         check=True).stdout.split()
    for module, path in zip(modules, out, strict=True):
        print(f"cpu: {module} -> {path}", flush=True)
        if not Path(path).resolve().is_relative_to(root):
            raise SystemExit(f"cpu: {module} is imported from {path}, not from {root}")


# ------------------------------------------------------------------ report
def median_table(runs: list[CpuRun], part: str) -> dict[str, float]:
    """Median over runs of CPU s per sim s, per process name (0 where a run lacked the process)."""
    names = sorted({n for r in runs for n in getattr(r, part)})
    table = {}
    for name in names:
        table[name] = statistics.median(getattr(r, part).get(name, 0.0) / r.sim_s(part) for r in runs)
    table["nav stack nodes (sum)"] = statistics.median(
        sum(v for n, v in getattr(r, part).items() if n in NAV_NODES) / r.sim_s(part) for r in runs)
    table["total"] = statistics.median(sum(getattr(r, part).values()) / r.sim_s(part) for r in runs)
    return table


def print_table(title: str, before: dict[str, float], after: dict[str, float]) -> list[str]:
    lines = [title, f"{'process':<26} {'before':>9} {'after':>9} {'after/before':>13}"]
    sums = ("nav stack nodes (sum)", "total")
    both = [n for n in before if n in after and n not in sums]
    one_side = [n for n in before if n not in after] + [n for n in after if n not in before]
    for name in [*both, *one_side, *sums]:
        b, a = before.get(name), after.get(name)
        ratio = f"{a / b:13.3f}" if a is not None and b else f"{'-':>13}"
        cells = [f"{v:9.4f}" if v is not None else f"{'-':>9}" for v in (b, a)]
        lines.append(f"{name:<26} {cells[0]} {cells[1]} {ratio}")
    for line in lines:
        print(f"cpu: {line}", flush=True)
    return lines


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each side, alternating")
    parser.add_argument("--before-commit", default=BEFORE_COMMIT)
    parser.add_argument("--keep-worktree", action="store_true", help="leave /tmp/navsuite_before")
    parser.add_argument("--note", default="", help="appended to every recorded row's note")
    parser.add_argument("--no-record", action="store_true")
    args = parser.parse_args()
    bench = Benchmark("cpu")
    domain = claim_domain_id()
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain))
    env.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    env.pop("PYTHONPATH", None)
    version = code_version_with_fingerprint()
    print(f"cpu: ROS_DOMAIN_ID {domain}; code {version}", flush=True)
    create_worktree(args.before_commit)
    before: list[CpuRun] = []
    after: list[CpuRun] = []
    try:
        benv = before_env(env)
        print("cpu: imports of the 'before' run:", flush=True)
        verify_imports(benv, WORKTREE, WORKTREE)
        print("cpu: imports of the 'after' run:", flush=True)
        verify_imports(env, REPO, REPO)
        sides = (
            ("before", before, [sys.executable, "-m", DEMO_MODULE, "--quiet", "--no-report"], WORKTREE, benv),
            ("after", after, demo_command("max"), REPO, env),
        )
        for index in range(args.runs):
            for label, results, command, cwd, side_env in sides:
                result = run_sampled(command, cwd, side_env)
                print(f"cpu: {label} run {index + 1}/{args.runs}: {result.run.describe()}", flush=True)
                print("cpu:     CPU s: " + ", ".join(f"{n} {v:.2f}" for n, v in sorted(result.whole.items()))
                      + f"; PYTHONPATH of the processes: {sorted(map(str, result.pythonpaths))}", flush=True)
                if label == "before" and any(p is None or not p.startswith(str(WORKTREE))
                                             for p in result.pythonpaths):
                    raise SystemExit("cpu: a 'before' process ran without the worktree on its PYTHONPATH")
                if not result.run.succeeded or result.run.sim_s <= 0.0 or len(result.run.stamps) < 2:
                    print("\n".join(result.run.output.splitlines()[-40:]), flush=True)
                    continue  # a failed run is reported, not measured
                results.append(result)
    finally:
        if not args.keep_worktree:
            remove_worktree()
    if not before or not after:
        print(f"cpu: no comparison: {len(before)} successful 'before' runs, {len(after)} 'after' runs",
              flush=True)
        return 1
    sims = (f"sim time median before {statistics.median(r.run.sim_s for r in before):.1f} s, "
            f"after {statistics.median(r.run.sim_s for r in after):.1f} s")
    note = (f"before = {args.before_commit} at rtf 1 (no lockstep, localization + navigation processes), "
            f"after = {version_note(version)} at rtf max lockstep; "
            f"median of {len(before)}/{len(after)} runs"
            + (f"; {args.note}" if args.note else ""))
    transit_before = statistics.median(r.sim_s("transit") for r in before)
    transit_after = statistics.median(r.sim_s("transit") for r in after)
    transits = (f"first to last transition median before {transit_before:.1f} sim s, "
                f"after {transit_after:.1f} sim s")
    for part, title, span in (("whole", "whole run", sims), ("mission", "mission", sims),
                              ("transit", "first to last transition", transits)):
        b, a = median_table(before, part), median_table(after, part)
        print_table(f"CPU s per sim s ({title}; {span})", b, a)
        if part == "mission":
            continue  # printed only: recorded are the whole run and the like-for-like transit
        for name in sorted(set(b) | set(a)):
            metric = f"CPU per sim second, {title}: {name}"
            if name in b:
                bench.record_value(f"{metric} (before)", b[name], "CPU s/sim s", f"{note}; {span}")
            if name in a:
                bench.record_value(f"{metric} (after)", a[name], "CPU s/sim s", f"{note}; {span}")
            if name in a and b.get(name):
                bench.record_value(f"{metric} (after / before)", a[name] / b[name], "x", f"{note}; {span}")
    bench.save()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
