"""Run a list of scenarios on an executor and judge each: the part ``navsuite-scenarios`` and the pytest
plugin share.

Selection (``select``) and artifact layout (``<out>/<scenario name>/``) live here too, so the command
and the plugin pick and store alike. Each run also records what ``navsuite-scenarios rerun`` needs to
replay one of its scenarios exactly: ``<out>/farm.json`` (the scenario file's path and SHA-256) and a
copy of the file, ``<out>/scenarios.yaml``. Ctrl-C (KeyboardInterrupt in the waiting thread) cancels the
executor: running workers get SIGTERM, queued ones never start, and their results say so.
"""

from __future__ import annotations

import fnmatch
import hashlib
import json
import shutil
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import replace
from pathlib import Path

from navsuite_tools.scenarios.executor import Executor, Job
from navsuite_tools.scenarios.schema import Scenario
from navsuite_tools.scenarios.schema_fields import INJECTED_EVENTS
from navsuite_tools.scenarios.summary import ScenarioResult
from navsuite_tools.scenarios.verdict import Outcome, judge

POLL = 0.5  # wall s between redraws of the live table while waiting
FARM_RECORD, SCENARIO_COPY = "farm.json", "scenarios.yaml"  # in a run's output directory


def select(scenarios: Sequence[Scenario], patterns: Sequence[str]) -> list[Scenario]:
    """Scenarios whose name contains one of ``patterns`` or matches it as a glob; all when none given."""
    if not patterns:
        return list(scenarios)
    return [s for s in scenarios
            if any(p in s.name or fnmatch.fnmatchcase(s.name, p) for p in patterns)]


def run_all(scenarios: Sequence[Scenario], source: Path, out_dir: Path, executor: Executor,
            on_start: Callable[[str], None] | None = None,
            on_done: Callable[[ScenarioResult], None] | None = None,
            tick: Callable[[], None] | None = None) -> list[ScenarioResult]:
    """Submit every scenario, wait for all; results in the file's order. KeyboardInterrupt cancels the
    rest, and is re-raised once every worker is down."""
    record_run(source, out_dir, [s.name for s in scenarios])
    futures: dict[Future[Outcome], Scenario] = {}
    for scenario in scenarios:
        job = Job(scenario, source, out_dir / scenario.name)
        start = (lambda name=scenario.name: on_start(name)) if on_start is not None else None
        futures[executor.submit(job, start)] = scenario
    results: dict[str, ScenarioResult] = {}
    pending = set(futures)
    try:
        while pending:
            done, pending = wait(pending, timeout=POLL, return_when=FIRST_COMPLETED)
            for future in done:
                result = _judged(futures[future], future)
                results[result.scenario.name] = result
                if on_done is not None:
                    on_done(result)
            if tick is not None:
                tick()
    except KeyboardInterrupt:
        executor.shutdown(cancel=True)
        raise
    executor.shutdown()
    return [results[s.name] for s in scenarios]


def file_digest(path: Path) -> str:
    """SHA-256 of a file's bytes (hex): whether a scenario file is still the one a run used."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def record_run(source: Path, out_dir: Path, names: Sequence[str]) -> None:
    """Write ``farm.json`` and the copy of ``source`` into ``out_dir`` (see the module docstring)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    record = {"source": str(source.resolve()), "sha256": file_digest(source), "scenarios": list(names)}
    (out_dir / FARM_RECORD).write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    if source.resolve() != (out_dir / SCENARIO_COPY).resolve():
        shutil.copyfile(source, out_dir / SCENARIO_COPY)


def _judged(scenario: Scenario, future: Future[Outcome]) -> ScenarioResult:
    try:
        outcome = future.result()
    except Exception as error:  # a backend fault fails its scenario, never the farm
        outcome = Outcome("ERROR", f"{type(error).__name__}: {error}")
    if future.cancelled():
        outcome = replace(outcome, result="ERROR", detail="cancelled")
    return ScenarioResult(scenario, outcome, judge(scenario.expect, outcome, injected_events(scenario)))


def injected_events(scenario: Scenario) -> int:
    """Events applied at sim time by the injector (schema_fields.INJECTED_EVENTS); battery levels go in
    before the start."""
    return sum(event.kind in INJECTED_EVENTS for event in scenario.events)
