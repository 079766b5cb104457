"""bench/RESULTS.md as a dashboard: the latest value of every metric, one table per area.

Why: the benchmarks' history is append-only (bench/history.jsonl, one JSON object per measured
figure), so the latest value of a metric sits among hundreds of older rows, experiments and A/B
pairs. This module keeps the history as it is and generates RESULTS.md from it: for each
(area, metric) its most recent row, with date, machine and note, and the target an issue set for
it (bench/targets.yaml) with whether the value meets it. Runs of the test suite (CI and by hand)
are kept apart in bench/ci_runs.jsonl: they measure the test suite, not the product.

Run ``.venv/bin/python -m bench.results_dashboard`` to regenerate RESULTS.md (bench/harness.py
does it after every benchmark that records), ``--check`` to only say whether it is up to date.
"""

from __future__ import annotations

import argparse
import fcntl
import fnmatch
import json
import re
import sys
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from pathlib import Path

import yaml

BENCH = Path(__file__).resolve().parent
HISTORY = BENCH / "history.jsonl"
CI_RUNS = BENCH / "ci_runs.jsonl"
TARGETS = BENCH / "targets.yaml"
RESULTS = BENCH / "RESULTS.md"


@dataclass(frozen=True)
class Row:
    """One recorded figure: the median (and range) of ``n`` samples of a metric, in ``unit``."""

    date: str  # ISO date of the measurement
    area: str  # the benchmark area, e.g. "planning"
    metric: str
    median: float
    min: float
    max: float
    unit: str
    n: int
    machine: str  # CPU model, logical cores and Python version
    note: str = ""

    @classmethod
    def from_json(cls, line: str) -> Row:
        return cls(**json.loads(line))

    def to_json(self) -> str:
        return json.dumps(asdict(self), ensure_ascii=False)


@dataclass(frozen=True)
class Target:
    """A bound an issue set for the metrics of one area that match ``metric`` (an fnmatch pattern)."""

    area: str
    metric: str
    issue: int
    at_least: float | None = None
    at_most: float | None = None

    def matches(self, row: Row) -> bool:
        return row.area == self.area and fnmatch.fnmatchcase(row.metric, self.metric)

    def met_by(self, value: float) -> bool:
        if self.at_least is not None:
            return value >= self.at_least
        return self.at_most is not None and value <= self.at_most

    def describe(self, unit: str) -> str:
        """E.g. '≥ 10 x (issue 44)'."""
        sign, bound = ("≥", self.at_least) if self.at_least is not None else ("≤", self.at_most)
        return f"{sign} {fmt(float(bound or 0.0))} {unit}".rstrip() + f" (issue {self.issue})"


def fmt(value: float) -> str:
    """Four significant digits, as the history's rows were always printed."""
    return f"{value:.4g}"


def read_rows(path: Path | None = None) -> list[Row]:
    """Every row of a JSON Lines file (default: the history), oldest first; a missing file is empty."""
    path = path or HISTORY
    if not path.exists():
        return []
    return [Row.from_json(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]


def append_rows(rows: Iterable[Row], path: Path | None = None) -> None:
    """Append rows to the history (or ``path``) under an exclusive lock, so two benchmarks finishing
    together never interleave their lines."""
    path = path or HISTORY
    text = "".join(row.to_json() + "\n" for row in rows)
    if not text:
        return
    with path.open("a", encoding="utf-8") as out:
        fcntl.flock(out, fcntl.LOCK_EX)
        out.write(text)


def load_targets(path: Path | None = None) -> list[Target]:
    """The targets file; each entry must give exactly one of at_least and at_most."""
    path = path or TARGETS
    entries = yaml.safe_load(path.read_text(encoding="utf-8")) if path.exists() else []
    targets = [Target(**entry) for entry in entries or []]
    for target in targets:
        if (target.at_least is None) == (target.at_most is None):
            raise ValueError(f"{path}: target {target.area}/{target.metric!r} needs one of at_least, at_most")
    return targets


def latest(rows: Iterable[Row]) -> dict[tuple[str, str], tuple[Row, int]]:
    """For each (area, metric): its last row (the history is in time order) and how many rows it has.

    The order is that of each metric's first appearance, so related metrics stay together.
    """
    found: dict[tuple[str, str], tuple[Row, int]] = {}
    for row in rows:
        key = (row.area, row.metric)
        found[key] = (row, found[key][1] + 1 if key in found else 1)
    return found


def _cell(text: str) -> str:
    return text.replace("|", "/").replace("\n", " ")


def _target_cell(row: Row, targets: list[Target]) -> str:
    hits = [target for target in targets if target.matches(row)]
    return "; ".join(f"{t.describe(row.unit)}: {'met' if t.met_by(row.median) else 'NOT MET'}" for t in hits)


def render(rows: list[Row], targets: list[Target], ci_runs: list[Row]) -> str:
    """The whole RESULTS.md page."""
    by_metric = latest(rows)
    areas: dict[str, list[tuple[Row, int]]] = {}
    for row, count in by_metric.values():
        areas.setdefault(row.area, []).append((row, count))
    lines = [
        "# Benchmark results",
        "",
        "Generated by `python -m bench.results_dashboard` from `bench/history.jsonl`: do not edit by hand.",
        "Each table holds the latest value of every metric of one area (the median of n samples), its date,",
        "machine and note, and the target where an issue set one (`bench/targets.yaml`). `rows` counts",
        "the metric's rows in the history, where the earlier values are. Numbers compare only within one",
        "machine. How to run the benchmarks: [docs/benchmarks.md](../docs/benchmarks.md).",
        "",
        f"{len(rows)} rows in the history, {len(by_metric)} metrics in {len(areas)} areas; "
        f"{len(ci_runs)} runs of the test suite are kept apart in `bench/ci_runs.jsonl`"
        + (f" (the latest on {ci_runs[-1].date})." if ci_runs else "."),
        "",
        "Areas: " + ", ".join(f"[{area}](#{area.lower().replace(' ', '-')})" for area in areas),
    ]
    for area, entries in areas.items():
        lines += ["", f"## {area}", "",
                  "| metric | value | unit | n | target | date | machine | rows | note |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for row, count in entries:
            lines.append(
                f"| {_cell(row.metric)} | {fmt(row.median)} | {row.unit} | {row.n} | "
                f"{_target_cell(row, targets)} | {row.date} | {row.machine} | {count} | {_cell(row.note)} |")
    return "\n".join(lines) + "\n"


_LEGACY_ROW = re.compile(r"^\| \d{4}-\d{2}-\d{2} \| ")


def salvage_legacy_rows() -> int:
    """Move rows appended to RESULTS.md in the old table format into the history; how many moved.

    Why: a benchmark started before the history existed still appends ``| date | area | ... |``
    rows (ten cells) to RESULTS.md when it ends. Regenerating the page would drop them, so they
    are carried over first; runs of the test suite go to ci_runs.jsonl.
    """
    if not RESULTS.exists():
        return 0
    rows = []
    for line in RESULTS.read_text(encoding="utf-8").splitlines():
        cells = [cell.strip() for cell in line.strip()[1:-1].split(" | ")]
        if _LEGACY_ROW.match(line) and len(cells) == 10:
            date, area, metric, median, low, high, unit, n, machine, note = cells
            rows.append(Row(date, area, metric, float(median), float(low), float(high), unit, int(n), machine,
                            note))
    append_rows([row for row in rows if row.area != "test suite"])
    append_rows([row for row in rows if row.area == "test suite"], CI_RUNS)
    return len(rows)


def generate() -> str:
    """What RESULTS.md should hold, from the history, the targets and the CI runs."""
    return render(read_rows(HISTORY), load_targets(TARGETS), read_rows(CI_RUNS))


def write_dashboard() -> Path:
    """Regenerate RESULTS.md (after salvaging any old-format rows in it); the path written."""
    salvage_legacy_rows()
    RESULTS.write_text(generate(), encoding="utf-8")
    return RESULTS


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 when bench/RESULTS.md is not what the history generates; write nothing")
    args = parser.parse_args(argv)
    if args.check:
        wanted = generate()
        current = RESULTS.read_text(encoding="utf-8") if RESULTS.exists() else ""
        if current != wanted:
            print(f"{RESULTS} is out of date: run python -m bench.results_dashboard", file=sys.stderr)
            return 1
        print(f"{RESULTS} is up to date")
        return 0
    print(f"wrote {write_dashboard()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
