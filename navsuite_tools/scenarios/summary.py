"""The farm's written results: ``junit.xml`` for CI and ``summary.html`` for people. Pure (stdlib).

JUnit: one testsuite per scenario file, one testcase per scenario (time = wall s); a failed criterion
is a ``<failure>`` whose message is the first failing criterion, a runner fault an ``<error>``. The
HTML shows the same table with each run's report image and links to its recording and logs; paths are
relative to the summary so the output directory can be moved or served as a CI artifact.
"""

from __future__ import annotations

import html
import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from navsuite_tools.scenarios.schema import Scenario
from navsuite_tools.scenarios.verdict import Outcome, Verdict


@dataclass(frozen=True)
class ScenarioResult:
    """A scenario with what its run gave and the judgement of it."""

    scenario: Scenario
    outcome: Outcome
    verdict: Verdict


def junit_xml(suite: str, results: Sequence[ScenarioResult]) -> str:
    """The JUnit XML document (a string, UTF-8 declaration included)."""
    errors = sum(r.outcome.result == "ERROR" for r in results)
    failures = sum(not r.verdict.passed for r in results) - errors
    root = ET.Element("testsuite", name=suite, tests=str(len(results)), failures=str(failures),
                      errors=str(errors), time=f"{sum(r.outcome.wall_time for r in results):.3f}")
    for result in results:
        case = ET.SubElement(root, "testcase", classname=f"scenarios.{suite}", name=result.scenario.name,
                             time=f"{result.outcome.wall_time:.3f}")
        if not result.verdict.passed:
            tag = "error" if result.outcome.result == "ERROR" else "failure"
            node = ET.SubElement(case, tag, message=result.verdict.failures[0], type=result.verdict.criterion)
            node.text = "\n".join([*result.verdict.failures, f"detail: {result.outcome.detail}"])
        out = [f"{key}: {value}" for key, value in result.outcome.to_json().items() if key != "artifacts"]
        out += [f"artifact {key}: {value}" for key, value in result.outcome.artifacts.items()]
        ET.SubElement(case, "system-out").text = "\n".join(out)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _number(value: float | int | None, digits: int = 2) -> str:
    return "–" if value is None else f"{value:.{digits}f}" if isinstance(value, float) else str(value)


def _result_text(outcome: Outcome) -> str:
    """The result word and its detail, without saying the word twice."""
    if not outcome.detail or outcome.detail.startswith(outcome.result):
        return outcome.detail or outcome.result
    return f"{outcome.result}: {outcome.detail}"


def summary_html(title: str, results: Sequence[ScenarioResult], base: Path, wall_s: float) -> str:
    """The HTML page; artifact paths are made relative to ``base`` (the page's directory)."""

    def link(path: str | None, text: str) -> str:
        if not path:
            return ""
        return f'<a href="{html.escape(os.path.relpath(path, base))}">{html.escape(text)}</a>'

    passed = sum(r.verdict.passed for r in results)
    rows = []
    for r in results:
        o, arts = r.outcome, r.outcome.artifacts
        status = "passed" if r.verdict.passed else "FAILED"
        image = ""
        if arts.get("report"):
            src = html.escape(os.path.relpath(arts["report"], base))
            image = f'<a href="{src}"><img src="{src}" width="360" alt="run report"></a>'
        rows.append(
            f'<tr class="{status}"><td>{html.escape(r.scenario.name)}</td><td>{status}</td>'
            f"<td>{html.escape(r.verdict.describe())}</td>"
            f"<td>{html.escape(_result_text(o))}</td>"
            f"<td>{_number(o.sim_time, 1)}</td><td>{_number(o.wall_time, 1)}</td>"
            f"<td>{_number(o.collisions)}</td>"
            f"<td>{_number(o.max_localization_error)}</td>"
            f"<td>{_number(o.min_clearance, 3)}</td>"
            f"<td>{link(arts.get('mcap'), 'mcap')} {link(arts.get('logs'), 'logs')}</td>"
            f"<td>{image}</td></tr>")
    head = ("<tr><th>scenario</th><th>verdict</th><th>criteria</th><th>result</th><th>sim s</th>"
            "<th>wall s</th><th>collisions</th><th>max loc. error m</th><th>min clearance m</th>"
            "<th>files</th><th>report</th></tr>")
    style = ("body{font-family:sans-serif}table{border-collapse:collapse}td,th{border:1px solid #ccc;"
             "padding:4px;vertical-align:top}tr.FAILED td:nth-child(2){color:#b00;font-weight:bold}"
             "tr.passed td:nth-child(2){color:#070}")
    return (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{style}</style></head><body><h1>{html.escape(title)}</h1>"
            f"<p>{passed} of {len(results)} scenarios passed; wall time {wall_s:.0f} s.</p>"
            f"<table>{head}{''.join(rows)}</table></body></html>\n")


def write_summary(out_dir: Path, suite: str, results: Sequence[ScenarioResult],
                  wall_s: float) -> tuple[Path, Path]:
    """Write ``summary.html`` and ``junit.xml`` into ``out_dir``; their paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    page, junit = out_dir / "summary.html", out_dir / "junit.xml"
    page.write_text(summary_html(f"Scenarios: {suite}", results, out_dir, wall_s), encoding="utf-8")
    junit.write_text(junit_xml(suite, results), encoding="utf-8")
    return page, junit
