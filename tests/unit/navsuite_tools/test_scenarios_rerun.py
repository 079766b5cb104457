"""navsuite-scenarios rerun (issue 43): a scenario of an earlier run replayed from the very file it used.

The executor here is a fake that "runs" a scenario by writing a synthetic recording
(tests/helpers/bag_synthetic.py) and a result, so the rule is tested without a stack: the same seed
is a replay identical to the recording, another seed is named with the sim time where the two part,
and a scenario file edited since the run, or a directory no farm wrote, is refused with what to do.
"""

from __future__ import annotations

import json
from concurrent.futures import Future
from pathlib import Path
from typing import Any

from navsuite_tools.scenarios.executor import Job
from navsuite_tools.scenarios.farm import FARM_RECORD, SCENARIO_COPY, run_all
from navsuite_tools.scenarios.rerun import EXIT_DIFFER, EXIT_SAME, EXIT_SETUP, rerun
from navsuite_tools.scenarios.schema import load_scenarios
from navsuite_tools.scenarios.verdict import Outcome
from tests.helpers.bag_synthetic import write_synthetic_run

SCENARIOS = """scenarios:
  - name: short
    mission: {goals: [[0.5, 0.0, 0.0]]}
  - name: other
    mission: {goals: [[-0.5, 0.0, 0.0]]}
"""


class SyntheticExecutor:
    """Runs a job by writing a synthetic recording of ``seed`` and its result.json."""

    def __init__(self, seed: int, result: str = "SUCCESS") -> None:
        self.seed, self.result = seed, result

    def submit(self, job: Job, on_start: Any = None) -> Future[Outcome]:
        job.artifact_dir.mkdir(parents=True, exist_ok=True)
        write_synthetic_run(job.artifact_dir / "run.mcap", seed=self.seed)
        outcome = Outcome(self.result, result_code=0, sim_time=14.8)
        (job.artifact_dir / "result.json").write_text(json.dumps(outcome.to_json()), encoding="utf-8")
        future: Future[Outcome] = Future()
        future.set_result(outcome)
        return future

    def shutdown(self, cancel: bool = False) -> None:
        pass


def _earlier_run(tmp_path: Path) -> tuple[Path, Path]:
    source = tmp_path / "mine.yaml"
    source.write_text(SCENARIOS, encoding="utf-8")
    run_dir = tmp_path / "run"
    run_all(load_scenarios(source), source, run_dir, SyntheticExecutor(seed=7))
    return source, run_dir


def test_a_run_records_its_scenario_file_and_the_same_inputs_replay_identically(tmp_path: Path) -> None:
    source, run_dir = _earlier_run(tmp_path)
    record = json.loads((run_dir / FARM_RECORD).read_text())
    assert record["source"] == str(source.resolve()) and record["scenarios"] == ["short", "other"]
    assert (run_dir / SCENARIO_COPY).read_text() == SCENARIOS
    lines: list[str] = []
    code = rerun(run_dir, "short", tmp_path / "again", SyntheticExecutor(seed=7), None, lines.append)
    assert code == EXIT_SAME, lines
    assert lines[-1].startswith("replay identical to the recording (identical:")
    assert "original: SUCCESS, result code 0, sim 14.80 s" in lines


def test_a_replay_that_parts_names_the_sim_time_and_topic_and_a_changed_result(tmp_path: Path) -> None:
    _, run_dir = _earlier_run(tmp_path)
    lines: list[str] = []
    code = rerun(run_dir, "short", tmp_path / "again", SyntheticExecutor(seed=8, result="ABORT"), None,
                 lines.append)
    assert code == EXIT_DIFFER, lines
    assert lines[-1] == ("replay differs: differ: first part at sim time 100.000 s on /amcl_pose; "
                         "result 'SUCCESS' then 'ABORT'"), lines[-1]


def test_an_edited_file_or_a_directory_no_farm_wrote_is_refused_with_what_to_do(tmp_path: Path) -> None:
    source, run_dir = _earlier_run(tmp_path)
    lines: list[str] = []

    def again(where: Path, name: str) -> int:
        return rerun(where, name, tmp_path / "again", SyntheticExecutor(seed=7), None, lines.append)

    source.write_text(SCENARIOS.replace("0.5, 0.0", "0.6, 0.0"), encoding="utf-8")
    assert again(run_dir, "short") == EXIT_SETUP
    assert "changed since that run" in lines[-1] and str(run_dir / SCENARIO_COPY) in lines[-1]
    assert again(tmp_path, "short") == EXIT_SETUP
    assert f"no {FARM_RECORD}" in lines[-1] and "navsuite-scenarios run FILE -k short" in lines[-1]
    source.write_text(SCENARIOS, encoding="utf-8")
    assert again(run_dir, "nope") == EXIT_SETUP
    assert "ran no scenario 'nope'; it ran: short, other" in lines[-1]
