"""bench/RESULTS.md is the dashboard of bench/history.jsonl: every metric with its latest value, no CI run."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from bench import harness, results_dashboard
from bench.results_dashboard import Row, Target, fmt, latest, load_targets, read_rows, render


def _row(metric: str, median: float, date: str = "2026-12-01", area: str = "planning") -> Row:
    return Row(date=date, area=area, metric=metric, median=median, min=median, max=median, unit="ms", n=1,
               machine="test machine ×2, py3.11", note="")


def _sections(page: str) -> dict[str, list[list[str]]]:
    """The table rows of each area of a RESULTS.md page, as lists of stripped cells."""
    sections: dict[str, list[list[str]]] = {}
    area = ""
    for line in page.splitlines():
        if line.startswith("## "):
            area = line[3:]
            sections[area] = []
        elif area and line.startswith("| ") and not line.startswith("| metric |"):
            sections[area].append([cell.strip() for cell in line.strip()[1:-1].split(" | ")])
    return sections


def test_every_metric_of_the_history_is_in_results_with_its_latest_value() -> None:
    page = results_dashboard.RESULTS.read_text(encoding="utf-8")
    sections = _sections(page)
    history = read_rows(results_dashboard.HISTORY)
    assert len(history) > 1000  # the history moved over whole, not a sample of it
    for (area, metric), (row, count) in latest(history).items():
        cells = [cells for cells in sections.get(area, []) if cells[0] == metric]
        assert len(cells) == 1, f"{area}: {metric!r} is missing from RESULTS.md (or listed twice)"
        assert cells[0][1] == fmt(row.median), f"{area}: {metric!r} shows {cells[0][1]}, not {row.median}"
        assert cells[0][5] == row.date and cells[0][7] == str(count)


def test_results_md_is_what_the_history_generates() -> None:
    assert results_dashboard.RESULTS.read_text(encoding="utf-8") == results_dashboard.generate(), \
        "bench/RESULTS.md is out of date: run .venv/bin/python -m bench.results_dashboard"


def test_ci_runs_are_kept_apart_and_not_in_results() -> None:
    page = results_dashboard.RESULTS.read_text(encoding="utf-8")
    ci_runs = read_rows(results_dashboard.CI_RUNS)
    assert ci_runs, "the test-suite runs moved to bench/ci_runs.jsonl"
    assert all(row.area == "test suite" for row in ci_runs)
    assert not any(row.area == "test suite" for row in read_rows(results_dashboard.HISTORY))
    assert "## test suite" not in page
    for row in ci_runs:
        assert row.metric not in page, f"a CI run is on the dashboard: {row.metric!r}"


def test_the_latest_row_of_a_metric_wins_and_rows_are_counted() -> None:
    rows = [_row("A* (warm)", 50.0, "2026-11-01"), _row("Theta*", 9.0), _row("A* (warm)", 42.0, "2026-11-02")]
    sections = _sections(render(rows, [], []))
    assert sections["planning"] == [
        ["A* (warm)", "42", "ms", "1", "", "2026-11-02", "test machine ×2, py3.11", "2", ""],
        ["Theta*", "9", "ms", "1", "", "2026-12-01", "test machine ×2, py3.11", "1", ""],
    ]


def test_a_target_says_whether_the_latest_value_meets_it() -> None:
    targets = [Target(area="planning", metric="* (warm)", issue=19, at_most=50.0)]
    fast, slow = _row("A* (warm)", 42.0), _row("Dijkstra (warm)", 236.5)
    cells = {cells[0]: cells[4] for cells in _sections(render([fast, slow], targets, []))["planning"]}
    assert cells == {"A* (warm)": "≤ 50 ms (issue 19): met", "Dijkstra (warm)": "≤ 50 ms (issue 19): NOT MET"}


def test_the_shipped_targets_load_and_each_matches_a_metric() -> None:
    targets = load_targets()
    metrics = [row for row, _ in latest(read_rows()).values()]
    for target in targets:
        assert any(target.matches(row) for row in metrics), f"target matches no metric: {target}"


def test_a_target_needs_exactly_one_bound(tmp_path: Path) -> None:
    bad = tmp_path / "targets.yaml"
    bad.write_text("- {area: a, metric: m, issue: 1}\n")
    with pytest.raises(ValueError, match="needs one of at_least, at_most"):
        load_targets(bad)


def test_a_benchmark_appends_to_the_history_and_regenerates_results(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(results_dashboard, "HISTORY", tmp_path / "history.jsonl")
    monkeypatch.setattr(results_dashboard, "CI_RUNS", tmp_path / "ci_runs.jsonl")
    monkeypatch.setattr(results_dashboard, "RESULTS", tmp_path / "RESULTS.md")
    results_dashboard.append_rows([_row("A* (warm)", 50.0, "2026-11-01")])
    bench = harness.Benchmark("planning", record_results=True)
    bench.record_value("A* (warm)", 41.234567, "ms", note="a | pipe")
    bench.save()
    history = read_rows()
    assert [row.median for row in history] == [50.0, 41.23]  # appended, four significant digits
    page = (tmp_path / "RESULTS.md").read_text(encoding="utf-8")
    assert re.search(r"^\| A\* \(warm\) \| 41\.23 \| ms \| 1 \|", page, re.MULTILINE)
    assert "a / pipe" in page and history[-1].note == "a | pipe"  # the history keeps the note as given


def test_rows_appended_in_the_old_table_format_are_moved_into_the_history(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A benchmark started before the move appends table rows to RESULTS.md; regenerating keeps them."""
    for name, file in (("HISTORY", "history.jsonl"), ("CI_RUNS", "ci_runs.jsonl"), ("RESULTS", "RESULTS.md")):
        monkeypatch.setattr(results_dashboard, name, tmp_path / file)
    results_dashboard.write_dashboard()
    legacy = ["| 2026-12-02 | planning | A* (warm) | 41.63 | 40 | 45.1 | ms | 6 | box ×2 | load 1.0 |",
              "| 2026-12-02 | test suite | `.ci/run` (run ZZ) | 9.5 | 9.5 | 9.5 | min | 1 | box ×2 | green |"]
    with (tmp_path / "RESULTS.md").open("a", encoding="utf-8") as page:
        page.write("\n".join(legacy) + "\n")
    results_dashboard.write_dashboard()
    assert read_rows() == [Row("2026-12-02", "planning", "A* (warm)", 41.63, 40.0, 45.1, "ms", 6, "box ×2",
                               "load 1.0")]
    assert [row.metric for row in read_rows(tmp_path / "ci_runs.jsonl")] == ["`.ci/run` (run ZZ)"]
    page_text = (tmp_path / "RESULTS.md").read_text(encoding="utf-8")
    assert "| A* (warm) | 41.63 | ms | 6 |" in page_text and "run ZZ" not in page_text
    results_dashboard.write_dashboard()
    assert len(read_rows()) == 1  # moved once, not again on the next regeneration
