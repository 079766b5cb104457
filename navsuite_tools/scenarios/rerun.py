"""``navsuite-scenarios rerun RUN_DIR NAME``: run one scenario of an earlier farm run again, and say whether
the replay is the recording.

Why: a scenario that failed once in CI is only worth a look if it can be had again. In lockstep every
input of a run is fixed by the scenario file (its seed, world, mission and events) and the code, so
the replay uses exactly the file the run used: the path and SHA-256 in the run's ``farm.json``
(navsuite_tools/scenarios/farm.py writes it). A file that changed since is refused, naming the run's copy
(``scenarios.yaml`` beside ``farm.json``): a replay of another scenario would prove nothing.

The verdict compares the two recordings topic by topic (navsuite_tools/bag/compare.py: the first sim time
where they part, and on which topic) and the two outcomes (result, Nav2 result code, sim time to the
tick). Exit status: 0 when both match, 1 when they differ, 2 when the replay cannot be set up.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from navsuite_tools.bag.compare import compare_recordings
from navsuite_tools.scenarios.executor import Executor
from navsuite_tools.scenarios.farm import FARM_RECORD, SCENARIO_COPY, file_digest, run_all
from navsuite_tools.scenarios.schema import Scenario, load_scenarios

EXIT_SAME, EXIT_DIFFER, EXIT_SETUP = 0, 1, 2
RECORDING = "run.mcap"  # a scenario's recording, in its artifact directory
#: the outcome's fields a replay must repeat (sim_time in s, as the worker writes it)
COMPARED = ("result", "result_code", "sim_time")


class RerunError(Exception):
    """The replay cannot be set up: the message says what is missing and what to do instead."""


@dataclass(frozen=True)
class Original:
    """What the earlier run left: the scenario file it used, the scenario, its outcome and recording."""

    source: Path
    scenario: Scenario
    outcome: dict[str, Any]
    recording: Path


def find_original(run_dir: Path, name: str, config_dir: Path | None) -> Original:
    """Read ``run_dir``'s record of scenario ``name``; RerunError when a replay would not be exact."""
    record_path = run_dir / FARM_RECORD
    if not record_path.is_file():
        raise RerunError(f"{run_dir}: no {FARM_RECORD} (not the output directory of a navsuite-scenarios "
                         "run, or of one older than rerun); run the scenario again with "
                         f"navsuite-scenarios run FILE -k {name}")
    record = json.loads(record_path.read_text(encoding="utf-8"))
    source = Path(record["source"])
    ran = record.get("scenarios", [])
    if name not in ran:
        raise RerunError(f"{run_dir} ran no scenario {name!r}; it ran: {', '.join(ran)}")
    copy = run_dir / SCENARIO_COPY
    if not source.is_file():
        raise RerunError(f"{source}, the scenario file of that run, is gone; its copy is {copy}")
    if file_digest(source) != record["sha256"]:
        raise RerunError(f"{source} changed since that run (its SHA-256 differs), so a replay would not be "
                         f"the same scenario; the run's version is {copy}")
    scenario = next((s for s in load_scenarios(source, config_dir) if s.name == name), None)
    if scenario is None:
        raise RerunError(f"{source} no longer defines {name!r}")
    artifacts = run_dir / name
    result_path, recording = artifacts / "result.json", artifacts / RECORDING
    for needed in (result_path, recording):
        if not needed.is_file():
            raise RerunError(f"{needed} is missing: that run did not finish {name!r}")
    return Original(source, scenario, json.loads(result_path.read_text(encoding="utf-8")), recording)


def outcome_line(outcome: dict[str, Any]) -> str:
    """``SUCCESS, result code 0, sim 14.80 s``."""
    sim = outcome.get("sim_time")
    return (f"{outcome.get('result')}, result code {outcome.get('result_code')}, "
            f"sim {'?' if sim is None else f'{sim:.2f}'} s")


def rerun(run_dir: Path, name: str, out_dir: Path, executor: Executor, config_dir: Path | None,
          say: Callable[[str], None] = print) -> int:
    """Replay ``name`` from ``run_dir`` into ``out_dir`` on ``executor``; say the verdict; the exit status."""
    try:
        original = find_original(run_dir, name, config_dir)
    except (RerunError, OSError, ValueError, KeyError) as error:
        say(f"navsuite-scenarios rerun: {error}")
        return EXIT_SETUP
    say(f"navsuite-scenarios rerun: {name} from {original.source} (as in {run_dir}); artifacts in {out_dir}/")
    result = run_all([original.scenario], original.source, out_dir, executor)[0]
    replay = result.outcome.to_json()
    say(f"original: {outcome_line(original.outcome)}")
    say(f"replay:   {outcome_line(replay)}")
    recording = out_dir / name / RECORDING
    if not recording.is_file():
        say(f"replay differs: it left no recording ({result.outcome.detail or result.outcome.result})")
        return EXIT_DIFFER
    comparison = compare_recordings(original.recording, recording)
    if comparison.report:
        say(comparison.report)
    parted = [field for field in COMPARED if original.outcome.get(field) != replay.get(field)]
    if comparison.identical and not parted:
        say(f"replay identical to the recording ({comparison.verdict})")
        return EXIT_SAME
    reasons = [comparison.verdict] if not comparison.identical else []
    reasons += [f"{field} {original.outcome.get(field)!r} then {replay.get(field)!r}" for field in parted]
    say("replay differs: " + "; ".join(reasons))
    return EXIT_DIFFER
