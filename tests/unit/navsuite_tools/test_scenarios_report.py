"""The farm's outputs without running anything: JUnit XML, the summary page, the live table's rows, the
domain-id claims, and ``pytest --scenarios`` collecting a file (collection only: no scenario runs)."""

from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from navsuite_tools.scenarios.domains import DomainPool, parse_range
from navsuite_tools.scenarios.schema import Expect, GoalsMission, Pose2D, Scenario
from navsuite_tools.scenarios.summary import ScenarioResult, junit_xml, summary_html
from navsuite_tools.scenarios.table import Row, row_text
from navsuite_tools.scenarios.verdict import Outcome, judge

REPO = Path(__file__).resolve().parents[3]
SELFTEST = REPO / "config" / "scenarios" / "farm_selftest.yaml"


def _result(name: str, outcome: Outcome) -> ScenarioResult:
    expect = Expect()
    mission = GoalsMission((Pose2D(0, 0),))
    scenario = Scenario(name, "turtlebot3_world", "waffle", None, mission, expect=expect)
    return ScenarioResult(scenario, outcome, judge(expect, outcome))


RESULTS = [
    _result("ok", Outcome("SUCCESS", sim_time=12.0, collisions=0, wall_time=8.0,
                          artifacts={"report": "/out/ok/report.png", "mcap": "/out/ok/run.mcap"})),
    _result("bad", Outcome("ABORT", "no path", collisions=0, wall_time=5.0)),
    _result("broken", Outcome("ERROR", "worker crashed", wall_time=1.0)),
]


def test_junit_has_one_case_per_scenario_with_the_criterion_as_the_failure_message() -> None:
    root = ET.fromstring(junit_xml("seed", RESULTS).split("\n", 1)[1])
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("3", "1", "1")
    cases = {case.get("name"): case for case in root.iter("testcase")}
    assert cases["ok"].find("failure") is None and cases["ok"].get("time") == "8.000"
    failure = cases["bad"].find("failure")
    assert failure is not None and failure.get("type") == "result"
    assert failure.get("message") == "result: expected SUCCESS, got ABORT (no path)"
    error = cases["broken"].find("error")
    assert error is not None and error.get("message") == "run: worker crashed"


def test_the_summary_page_shows_verdicts_criteria_and_report_images_relative_to_it() -> None:
    page = summary_html("Scenarios: seed", RESULTS, Path("/out"), 20.0)
    assert "1 of 3 scenarios passed" in page
    assert '<img src="ok/report.png"' in page and 'href="ok/run.mcap"' in page
    assert "result: expected SUCCESS, got ABORT (no path)" in page


def test_a_row_names_the_first_failing_criterion_or_the_sim_time() -> None:
    failed, passed = RESULTS[1], RESULTS[0]
    assert row_text(Row("bad", "FAILED", None, failed.outcome, failed.verdict), 6, 0.0) == \
        "bad     FAILED     5.0 s  result: expected SUCCESS, got ABORT (no path)"
    assert row_text(Row("ok", "passed", None, passed.outcome, passed.verdict), 2, 0.0) == \
        "ok  passed     8.0 s  sim 12.0 s"
    assert row_text(Row("r", "running", 10.0), 1, 12.5) == "r  running    2.5 s"


def test_domain_ranges_parse_and_bad_ones_are_refused() -> None:
    assert parse_range("86-99") == (86, 99) and parse_range("120") == (120, 120)
    for bad in ("x-9", "99-86", "200-300"):
        with pytest.raises(ValueError, match="expected"):
            parse_range(bad)


def test_two_claims_never_get_the_same_domain_and_a_release_frees_it() -> None:
    pool = DomainPool(231, 232, timeout=0.0)
    with pool.claim() as first, pool.claim() as second:
        assert {first, second} == {231, 232}
        with pytest.raises(RuntimeError, match=r"no free ROS domain id in 231\.\.232"), pool.claim():
            pass
    with pool.claim() as again:
        assert again == 231


def _pytest(*args: str) -> subprocess.CompletedProcess[str]:
    """pytest in a subprocess with only this plugin (entry points off: the plugin may be installed too)."""
    env = dict(os.environ, PYTEST_DISABLE_PLUGIN_AUTOLOAD="1")
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "navsuite_tools.scenarios.pytest_plugin",
                           "-p", "no:cacheprovider", *args],
                          cwd=REPO, env=env, capture_output=True, text=True, timeout=120)


def test_pytest_collects_one_test_per_scenario_of_the_file() -> None:
    run = _pytest("--scenarios", str(SELFTEST), "--collect-only", "-q")
    assert run.returncode == 0, run.stdout + run.stderr
    names = [line for line in run.stdout.splitlines() if "::" in line]
    assert names == [f"config/scenarios/farm_selftest.yaml::{n}"
                     for n in ("short_goal", "unreachable_goal_aborts", "built_to_fail")]


def test_pytest_reports_an_invalid_scenario_file_naming_the_field(tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("scenarios:\n  - {name: x, robot: roomba, mission: {goals: [[0, 0]]}}\n")
    run = _pytest("--scenarios", str(bad), "--collect-only", "-q")
    assert run.returncode != 0
    assert "scenario 'x': robot: unknown robot (got 'roomba')" in run.stdout


def test_the_sweep_kills_every_process_carrying_the_run_marker() -> None:
    from navsuite_tools.scenarios.executor import MARKER, marked_processes, sweep

    env = dict(os.environ, **{MARKER: "unit-test:sweep"})
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"], env=env)
    try:
        assert marked_processes("unit-test:sweep") == [child.pid]
        assert sweep("unit-test:sweep") == 1
        assert child.wait(timeout=10) == -9
        assert marked_processes("unit-test:sweep") == []
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def test_the_row_and_the_summary_show_the_smallest_clearance() -> None:
    outcome = Outcome("SUCCESS", sim_time=12.0, collisions=0, wall_time=8.0, min_clearance=0.0734)
    result = _result("cm", outcome)
    assert row_text(Row("cm", "passed", None, outcome, result.verdict), 2, 0.0) == \
        "cm  passed     8.0 s  sim 12.0 s, clearance 0.073 m"
    page = summary_html("Scenarios: cm", [result], Path("/out"), 10.0)
    assert "<th>min clearance m</th>" in page and "<td>0.073</td>" in page
    assert "min_clearance: 0.0734" in junit_xml("cm", [result])
