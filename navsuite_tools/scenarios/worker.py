"""Run one scenario in this process's children and write its ``result.json``: the farm's unit of work.

``python -m navsuite_tools.scenarios.worker FILE NAME ARTIFACT_DIR`` runs scenario NAME of FILE on the
ROS_DOMAIN_ID it was started with (the executor picks a free one). It starts the processes of
``commands.plan`` through ros_tools.launch (each one's log in ``ARTIFACT_DIR/logs/<name>.log``): the
recorder and the event injector when needed, then the mission command, or nav-bringup followed by
the goal driver. It reads the mission's result from the command's lines, collisions
and localization error from the recording, writes the run report PNG when the command did not, and
writes ``result.json`` (a verdict.Outcome). Exit status 0 once the result is written, whatever it says.

SIGINT or SIGTERM stops the run (the launcher's orderly shutdown: recorders close their files); every
child also gets SIGTERM from the kernel if this process dies (ros_tools.launch's PR_SET_PDEATHSIG).
"""

from __future__ import annotations

import json
import os
import re
import sys
import time
from collections.abc import Sequence
from dataclasses import asdict, replace
from pathlib import Path

from navsuite_data import data_dir, data_root
from navsuite_tools.scenarios import commands, outcome
from navsuite_tools.scenarios.schema import Scenario, load_scenarios
from navsuite_tools.scenarios.schema_fields import INJECTED_EVENTS
from navsuite_tools.scenarios.verdict import Outcome
from ros_tools.launch import Launcher, LaunchError, ProcessSpec

READY = r"Nav2 is ready"
READY_TIMEOUT = 180.0  # wall s for nav-bringup's readiness line
RESULT_FILE = "result.json"
LAYOUT_ENV = "NAVSUITE_LAYOUT"  # nav-bringup's default process layout (one-process or isolated)
APPLIED = re.compile(r"^applied .*")
#: sim2d's warnings for an event it did not apply ("teleport to <pose> refused: footprint overlaps ...",
#: "obstacle at (x, y) radius r m refused: it overlaps the robot")
REFUSED = re.compile(r"(teleport to|obstacle at) .* refused")
#: nav-bringup's line for a process that died and ends the launch (the simulator, or a respawn given up)
DIED = re.compile(r"ERROR: .*\bdied\b")


def record_spec(mcap: Path) -> ProcessSpec:
    """navsuite-bag record of commands.RECORDED_TOPICS (a regex: a listed topic may never appear)."""
    pattern = "^(" + "|".join(re.escape(topic) for topic in commands.RECORDED_TOPICS) + ")$"
    return ProcessSpec("scenario-record", [*commands.executable("navsuite-bag"), "record", "-e", pattern,
                                           "--use-sim-time", "-o", str(mcap)], required=False)


def injector_spec(scenario: Scenario) -> ProcessSpec | None:
    """The injector of the events applied during the run (schema_fields.INJECTED_EVENTS), if any."""
    events = [{"at": e.at, e.kind: e.value.as_list() if e.kind == "kidnap" else e.value}
              for e in scenario.events if e.kind in INJECTED_EVENTS]
    if not events:
        return None
    return ProcessSpec("scenario-events", [sys.executable, "-m", "navsuite_tools.scenarios.injector",
                                           json.dumps(events)], required=False)


def with_participant(plan: commands.RunPlan, role: str) -> commands.RunPlan:
    """The plan with ``role`` among the lockstep participants the simulator waits for at start."""
    if plan.stack is not None:
        return replace(plan, stack=[*plan.stack, "--participant", role])
    mission = list(plan.mission)
    if "--bringup" in mission:  # navsuite-demo: the stack's command line is one argument
        index = mission.index("--bringup") + 1
        mission[index] = f"{mission[index]} --participant {role}"
    else:  # sm-battery-patrol
        mission += ["--bringup-arg=--participant", f"--bringup-arg={role}"]
    return replace(plan, mission=mission)


def run(scenario: Scenario, artifact_dir: Path) -> Outcome:
    """Run ``scenario`` with its artifacts in ``artifact_dir``; the facts of the run."""
    started = time.monotonic()
    artifact_dir.mkdir(parents=True, exist_ok=True)
    plan = commands.plan(scenario, artifact_dir, data_root())
    for path, text in plan.files.items():
        path.write_text(text, encoding="utf-8")
    injector = injector_spec(scenario)
    if injector is not None:
        plan = with_participant(plan, "scenario_events")
    if scenario.isolated:  # localization as a process of its own, for its kill/freeze events
        os.environ[LAYOUT_ENV] = "isolated"
    launcher = Launcher(output=lambda line: print(line, flush=True), color=False,
                        log_dir=artifact_dir / "logs", show=lambda _line: False)
    deadline = started + scenario.timeout + commands.COMMAND_MARGIN
    with launcher.stopping_on_signals() as interrupted:
        try:
            facts, code = _supervise(plan, launcher, [injector] if injector else [], deadline)
            if interrupted.is_set():
                facts, code = outcome.MissionFacts("ERROR", "interrupted (the farm was stopped)"), code
        finally:
            launcher.shutdown()
    applied = _applied_events(artifact_dir / "logs")
    return _finish(plan, facts, code, applied, time.monotonic() - started)


def _supervise(plan: commands.RunPlan, launcher: Launcher, extra: list[ProcessSpec],
               deadline: float) -> tuple[outcome.MissionFacts, int | None]:
    """Start the plan's processes, wait for the mission's end; its facts and exit code."""
    assert launcher.log_dir is not None
    stack_proc = None
    try:
        # The recorder first: it finds topics by polling the graph, and started after the stack it
        # could miss /amcl_pose for the whole of a run that lasts a second of wall time (the
        # selftest's short_goal: "max_localization_error: not measured" in 1 of 4 runs).
        if plan.record:
            launcher.start([record_spec(plan.mcap)])
        if plan.stack is not None:
            stack = ProcessSpec("scenario-stack", plan.stack, ready=READY, ready_timeout=READY_TIMEOUT)
            launcher.start([stack])
            stack_proc = launcher.running[-1].proc
        launcher.start(extra)
        launcher.start([ProcessSpec("scenario-mission", plan.mission)])
    except LaunchError as error:
        return outcome.MissionFacts("STACK", f"did not start: {error}"), None
    launcher.wait(lambda: time.monotonic() > deadline)
    mission = launcher.running[-1].proc
    stack_code = stack_proc.poll() if stack_proc is not None else None
    stopped = mission.poll() is None
    launcher.shutdown()  # the mission's last lines and the recording's end are written by now
    lines = _lines(launcher.log_dir / "scenario-mission.log")
    if stopped and stack_code is not None:  # nav-bringup ended under a goal list or a tree: say why
        return outcome.MissionFacts("STACK", _stack_stopped(launcher.log_dir, stack_code)), None
    if stopped:
        return outcome.MissionFacts("TIMEOUT", "the farm stopped the run at its deadline"), None
    if plan.kind == "tree":
        return outcome.tree_facts(lines, mission.returncode), mission.returncode
    if plan.kind == "goals":
        return outcome.goal_facts(lines, mission.returncode), mission.returncode
    facts = outcome.machine_facts(lines, mission.returncode)
    if facts.result == "STACK":  # the command's own stack (navsuite-demo's nav-bringup): name the death
        died = [line.strip() for line in lines if DIED.search(line)]
        if died:
            facts = replace(facts, detail=f"{facts.detail}: {died[-1]}")
    return facts, mission.returncode


def _stack_stopped(logs: Path, code: int) -> str:
    """Why the stack the worker started ended: nav-bringup's last ERROR line (which process died)."""
    errors = [line.strip() for line in _lines(logs / "scenario-stack.log") if "ERROR" in line]
    return f"the stack stopped (exit code {code})" + (f": {errors[-1]}" if errors else "")


def _applied_events(logs: Path) -> tuple[str, ...]:
    """The injector's "applied" lines, less the teleports sim2d refused (a pose inside an obstacle)."""
    sent = [line for line in _lines(logs / "scenario-events.log") if APPLIED.match(line)]
    refused = sum(REFUSED.search(line) is not None for line in _lines(logs / "sim2d.log"))
    return tuple(sent[: max(0, len(sent) - refused)])


def _finish(plan: commands.RunPlan, facts: outcome.MissionFacts, code: int | None,
            applied: tuple[str, ...], wall: float) -> Outcome:
    """Add the recording's numbers and the report to the mission's facts."""
    from navsuite_tools.scenarios.metrics import measure

    artifacts = {"logs": str(plan.report.parent / "logs")}
    collisions = error = span = clearance = None
    if plan.mcap.exists():
        artifacts["mcap"] = str(plan.mcap)
        try:
            metrics = measure(plan.mcap)
            collisions, error, span = metrics.collisions, metrics.max_localization_error, metrics.sim_span
            clearance = metrics.min_clearance
        except Exception as exc:  # a broken recording leaves the criteria "not measured", never a crash
            print(f"[scenario] cannot read {plan.mcap}: {exc}", flush=True)
        if not plan.report.exists():
            _write_report(plan)
    if plan.report.exists():
        artifacts["report"] = str(plan.report)
    mission = asdict(facts) | {"sim_time": facts.sim_time if facts.sim_time is not None else span}
    return Outcome(**mission, collisions=collisions, max_localization_error=error, min_clearance=clearance,
                   exit_code=code, wall_time=wall, events_applied=applied, artifacts=artifacts)


def _write_report(plan: commands.RunPlan) -> None:
    from navsuite_tools.report.render import write_report

    try:
        write_report(plan.mcap, plan.report)
    except Exception as exc:  # a report must never turn a finished run into an error
        print(f"[scenario] no run report: {exc}", flush=True)


def _lines(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return []


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 3:
        print("usage: python -m navsuite_tools.scenarios.worker FILE NAME ARTIFACT_DIR", file=sys.stderr)
        return 2
    source, name, artifact_dir = Path(args[0]), args[1], Path(args[2])
    scenario = next(s for s in load_scenarios(source, data_dir("config")) if s.name == name)
    result = Outcome("ERROR", "interrupted before the run ended")
    try:
        result = run(scenario, artifact_dir)
    except Exception as error:  # the farm gets an ERROR result naming the fault, not a missing file
        result = Outcome("ERROR", f"{type(error).__name__}: {error}")
        raise
    finally:
        (artifact_dir / RESULT_FILE).write_text(json.dumps(result.to_json(), indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
