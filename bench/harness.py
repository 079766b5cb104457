"""A small benchmark harness shared by every benchmark under bench/.

Why: speed is measured, never asserted. Each benchmark times a callable N times, prints
median/min/max, and appends one dated row per metric to bench/history.jsonl together with the
machine's CPU model, core count and Python version, so results from different days and machines
can be compared side by side. It then regenerates bench/RESULTS.md, the dashboard of the latest
value of every metric (bench/results_dashboard.py).

Usage::

    from bench.harness import Benchmark

    bench = Benchmark("sim2d")
    stats = bench.time("physics+lidar step", step, repeat=200, warmup=10)   # seconds per call
    bench.record("physics+lidar step", stats.median * 1e3, "ms", note="waffle, 360 beams")
    bench.record_value("node real-time factor (max mode)", 143.0, "x")
    bench.save()                                  # append to history.jsonl, regenerate RESULTS.md

Run one benchmark with ``.venv/bin/python -m bench.<module>``; ``--no-record`` prints only.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import fcntl
import os
import platform
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from bench import results_dashboard
from bench.results_dashboard import Row

REPO = Path(__file__).resolve().parents[1]


def machine_description() -> str:
    """CPU model, logical cores and Python version, e.g. 'AMD EPYC 7B13 ×2, py3.11'."""
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model} ×{os.cpu_count()}, py{sys.version_info.major}.{sys.version_info.minor}"


_DOMAIN_LOCKS: list[object] = []


def claim_domain_id() -> int:
    """A ROS_DOMAIN_ID (1..100) no test session or other benchmark on this machine holds; held until exit.

    Same lock files as tests/conftest.py (``navsuite-ros-domain-<id>.lock``, an exclusive flock each),
    so a benchmark never shares a DDS domain with a test run on the same machine. 1..100 keeps the
    DDS ports below Linux's ephemeral port range.
    """
    start = os.getpid() % 100
    for offset in range(100):
        domain = 1 + (start + offset) % 100
        handle = open(os.path.join(tempfile.gettempdir(), f"navsuite-ros-domain-{domain}.lock"), "w")  # noqa: SIM115
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        _DOMAIN_LOCKS.append(handle)  # released when this process exits
        return domain
    raise RuntimeError("all ROS domain ids 1..100 are held by test sessions or benchmarks on this machine")


def enter_local_domain() -> str:
    """Keep this benchmark's DDS on this machine and in a domain of its own: sets
    ROS_AUTOMATIC_DISCOVERY_RANGE (LOCALHOST unless set) and ROS_DOMAIN_ID (claim_domain_id() unless
    set) for this process and the stack it starts. The domain id, for the benchmark's first line."""
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    if "ROS_DOMAIN_ID" not in os.environ:
        os.environ["ROS_DOMAIN_ID"] = str(claim_domain_id())  # never a test session's domain
    return os.environ["ROS_DOMAIN_ID"]


def _git(*args: str) -> str:
    import subprocess

    return subprocess.run(["git", "-C", str(REPO), *args], capture_output=True,
                          text=True).stdout


def code_version() -> str:
    """The checkout being measured: ``<HEAD>``, plus ``+dirty:<hash>`` when files outside bench/ differ
    from HEAD (the hash names that diff)."""
    import hashlib

    head = _git("rev-parse", "--short", "HEAD").strip() or "unknown"
    diff = _git("diff", "HEAD", "--", ".", ":(exclude)bench")
    untracked = _git("ls-files", "--others", "--exclude-standard", "--", ".", ":(exclude)bench")
    if not diff and not untracked:
        return head
    return f"{head}+dirty:{hashlib.sha1((diff + untracked).encode()).hexdigest()[:8]}"


def _stack_fingerprint() -> str:
    """A hash of every file outside bench/ as the working tree has it (HEAD's tree plus local changes)."""
    import hashlib

    tree = "".join(line for line in _git("ls-tree", "HEAD").splitlines(keepends=True)
                   if not line.rstrip().endswith("\tbench"))
    diff = _git("diff", "HEAD", "--", ".", ":(exclude)bench")
    untracked = _git("ls-files", "--others", "--exclude-standard", "--", ".", ":(exclude)bench")
    return hashlib.sha1((tree + diff + untracked).encode()).hexdigest()


_FINGERPRINTS: dict[str, str] = {}


def code_version_with_fingerprint() -> str:
    """code_version(), remembering what the files outside bench/ were for version_note()."""
    version = code_version()
    _FINGERPRINTS[version] = _stack_fingerprint()
    return version


def version_note(started: str) -> str:
    """``code <version>``; says so when the checkout changed since ``started`` (a code_version()):
    a new HEAD that changed only bench/ is named but is not a change of the code measured."""
    now = code_version()
    if now == started:
        return f"code {now}"
    if started in _FINGERPRINTS and _FINGERPRINTS[started] == _stack_fingerprint():
        return f"code {started} (HEAD moved to {now} during the run, bench/ only)"
    return f"CODE CHANGED DURING THE RUN: {started} -> {now}"


@dataclass(frozen=True)
class Stats:
    """Summary of repeated measurements (same unit as the samples)."""

    median: float
    minimum: float
    maximum: float
    count: int

    @classmethod
    def of(cls, samples: list[float]) -> Stats:
        if not samples:
            raise ValueError("no samples")
        return cls(statistics.median(samples), min(samples), max(samples), len(samples))


def parse_cli(description: str | None) -> argparse.Namespace:
    """The command line of a benchmark without options of its own: ``--no-record`` and ``--help``.

    Why: without a parser, ``--help`` (or a mistyped option) ran the whole benchmark on a possibly
    busy machine and appended its rows to the history.
    """
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--no-record", action="store_true",
                        help="print only; do not append to bench/history.jsonl")
    return parser.parse_args()


@dataclass
class Benchmark:
    """Collects the rows of one benchmark area and appends them to bench/history.jsonl."""

    suite: str  # the area the rows belong to, e.g. "planning"
    record_results: bool = field(default_factory=lambda: "--no-record" not in sys.argv)
    rows: list[Row] = field(default_factory=list)

    def time(self, label: str, fn: Callable[[], object], repeat: int = 50, warmup: int = 3) -> Stats:
        """Call ``fn`` ``warmup`` times untimed, then ``repeat`` times; return seconds per call."""
        for _ in range(warmup):
            fn()
        samples = []
        for _ in range(repeat):
            started = time.perf_counter()
            fn()
            samples.append(time.perf_counter() - started)
        stats = Stats.of(samples)
        print(
            f"{self.suite}: {label}: median {stats.median * 1e3:.3f} ms "
            f"(min {stats.minimum * 1e3:.3f}, max {stats.maximum * 1e3:.3f}, n={stats.count})",
            flush=True,
        )
        return stats

    def record(self, metric: str, stats: Stats, unit: str, scale: float = 1.0, note: str = "") -> None:
        """Queue a row for ``stats`` (multiplied by ``scale``, e.g. 1e3 for seconds → ms)."""
        self._add(metric, stats.median * scale, stats.minimum * scale, stats.maximum * scale, unit,
                  stats.count, note)

    def record_value(self, metric: str, value: float, unit: str, note: str = "") -> None:
        """Queue a row for a single figure (a success rate, an RMS error, a real-time factor)."""
        print(f"{self.suite}: {metric}: {value:.4g} {unit} {note}".rstrip(), flush=True)
        self._add(metric, value, value, value, unit, 1, note)

    def _add(self, metric: str, median: float, low: float, high: float, unit: str, n: int,
             note: str) -> None:
        # Four significant digits, as printed: the history records what a reader saw.
        self.rows.append(Row(date=_dt.date.today().isoformat(), area=self.suite, metric=metric,
                             median=float(f"{median:.4g}"), min=float(f"{low:.4g}"),
                             max=float(f"{high:.4g}"), unit=unit, n=n, machine=machine_description(),
                             note=note))

    def save(self) -> None:
        """Append the queued rows to bench/history.jsonl and regenerate bench/RESULTS.md."""
        if not self.record_results or not self.rows:
            return
        results_dashboard.append_rows(self.rows)
        dashboard = results_dashboard.write_dashboard()
        print(f"{self.suite}: {len(self.rows)} rows appended to {results_dashboard.HISTORY}; "
              f"{dashboard} regenerated")
        self.rows.clear()
