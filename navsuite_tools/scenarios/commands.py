"""The processes that run one scenario: existing mission commands, driven by their documented options.

Pure: ``plan(scenario, artifact_dir, data_root)`` returns the command lines and the parameter overlays to
write; the worker starts them. Each mission kind reuses the command that already runs it, so a
scenario behaves exactly like the same run started by hand:

* ``sm_nav2_test_1``: ``navsuite-demo`` (records the run and writes its report itself). Its stack is
  started through ``--bringup`` so world and start pose reach nav-bringup;
* ``sm_battery_patrol``: ``sm-battery-patrol`` (world and start through ``--bringup-arg``);
* goals: ``nav-bringup`` with navsuite_tools.scenarios.goal_driver as its lockstep participant;
* behavior tree: ``nav-bringup`` with ``nav-autonomy`` as its lockstep participant.

The worker records the runs that do not record themselves (navsuite-bag record, the demo's topics).
Everything runs at ``--rtf max`` in lockstep (the commands' default).
"""

from __future__ import annotations

import json
import shlex
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from navsuite_tools.scenarios.schema import BehaviorTreeMission, GoalsMission, Scenario, StateMachineMission
from navsuite_tools.scenarios.schema_fields import MACHINES

#: console script → module, for an environment where the scripts are not installed next to Python.
MODULES = {"navsuite-demo": "smacc_py.state_machines.sm_nav2_test_1.demo",
           "sm-battery-patrol": "smacc_py.state_machines.sm_battery_patrol.demo",
           "nav-bringup": "nav_stack.ros.bringup.nav_bringup",
           "nav-autonomy": "nav_stack.ros.autonomy.node", "navsuite-bag": "navsuite_tools.bag.main"}
#: What the worker records when the mission command does not (navsuite-demo's REPORT + REPLAY topics).
#: /sim2d/clearance feeds the min_clearance criterion, /collision_monitor_state shows why the robot stopped.
RECORDED_TOPICS = ("/map", "/ground_truth", "/amcl_pose", "/plan", "/goal_pose", "/sim2d/collisions",
                   "/scan", "/odom", "/tf", "/tf_static", "/cmd_vel", "/local_plan", "/battery_state",
                   "/SmBatteryPatrol/smacc/transition_log", "/sim2d/clearance", "/collision_monitor_state")
BATTERY_SIM_PARAMS = "config/sim2d_battery_patrol.yaml"  # the seed's fast-draining battery
#: wall s a run may take beyond its mission's own timeout (bringup, shutdown, report): the worker stops the
#: mission then (goal lists and trees have no timeout of their own), the executor later (executor.KILL_AFTER)
COMMAND_MARGIN = 45.0


@dataclass(frozen=True)
class RunPlan:
    """What the worker starts, in order: ``stack`` (when it runs nav-bringup itself), then the
    ``mission`` command, whose end is the run's end. ``files`` are written first."""

    kind: str  # "machine", "goals" or "tree"
    mission: list[str]
    stack: list[str] | None = None
    files: dict[Path, str] = field(default_factory=dict)
    record: bool = True
    mcap: Path = Path("run.mcap")
    report: Path = Path("report.png")


def executable(script: str) -> list[str]:
    """The console script next to this Python (a venv's bin/), else ``python -m <module>``."""
    beside = Path(sys.executable).parent / script
    return [str(beside)] if beside.exists() else [sys.executable, "-m", MODULES[script]]


def plan(scenario: Scenario, artifact_dir: Path, data_root: Path) -> RunPlan:
    """The commands and overlays of ``scenario``, its artifacts under ``artifact_dir``; ``data_root``
    holds the shipped config/ (navsuite_data.data_root(): the repository in a checkout)."""
    logs = artifact_dir / "logs"
    report = artifact_dir / "report.png"
    mission = scenario.mission
    files: dict[Path, str] = {}
    drains = isinstance(mission, BehaviorTreeMission) or (
        isinstance(mission, StateMachineMission) and mission.machine == "sm_battery_patrol")
    base_sim = data_root / BATTERY_SIM_PARAMS if drains else None
    sim_params = _sim_overlay(scenario, base_sim)
    sim_file = artifact_dir / "sim2d_overlay.yaml"
    if sim_params is not None:
        files[sim_file] = yaml.safe_dump(sim_params, sort_keys=False)
    sim_arg = ["--sim-params", str(sim_file)] if sim_params is not None else []
    place = _placement(scenario)
    timeout = f"{scenario.timeout:g}"
    if isinstance(mission, StateMachineMission):
        params_file = artifact_dir / f"{mission.machine}.yaml"
        files[params_file] = yaml.safe_dump(_machine_params(scenario, mission, data_root), sort_keys=False)
        common = ["--rtf", "max", "--timeout", timeout, "--params-file", str(params_file),
                  "--log-dir", str(logs), "--robot", scenario.robot]
        if mission.machine == "sm_nav2_test_1":
            bringup = shlex.join([*executable("nav-bringup"), *place, *sim_arg, "--log-dir", str(logs),
                                  "--participant", "SmNav2Test1"])
            command = [*executable("navsuite-demo"), *common, "--report", str(report), "--bringup", bringup]
            return RunPlan("machine", command, files=files, record=False, mcap=report.with_suffix(".mcap"),
                           report=report)
        command = [*executable("sm-battery-patrol"), *common, *sim_arg, "--cycles", str(mission.cycles or 1),
                   *(f"--bringup-arg={arg}" for arg in place)]
        return RunPlan("machine", command, files=files, mcap=artifact_dir / "run.mcap", report=report)
    stack = [*executable("nav-bringup"), "--rtf", "max", "--robot", scenario.robot, *place, *sim_arg,
             "--log-dir", str(logs)]
    if isinstance(mission, GoalsMission):
        goals = json.dumps([goal.as_list() for goal in mission.goals])
        command = [sys.executable, "-m", "navsuite_tools.scenarios.goal_driver", goals,
                   "--wait-for", "/ground_truth"]
        if mission.max_goal_time is not None:
            command += ["--goal-time", f"{mission.max_goal_time:g}"]
        return RunPlan("goals", command, [*stack, "--participant", "scenario_goals"], files,
                       mcap=artifact_dir / "run.mcap", report=report)
    assert isinstance(mission, BehaviorTreeMission)
    command = [*executable("nav-autonomy"), "--tree", str(mission.tree),
               "--locations", str(mission.locations), "--max-cycles", str(mission.max_cycles),
               "--ros-args", "-p", "use_sim_time:=true"]
    return RunPlan("tree", command, [*stack, "--participant", "autonomy"], files,
                   mcap=artifact_dir / "run.mcap", report=report)


def _placement(scenario: Scenario) -> list[str]:
    """nav-bringup's world and spawn (which is also AMCL's initial pose), and the scenario's parameter
    files (each a ``--params``, in order)."""
    args = ["--world", scenario.world]
    for path in scenario.params:
        args += ["--params", str(path)]
    if scenario.start is not None:
        start = scenario.start
        args += [f"--x={start.x:g}", f"--y={start.y:g}", f"--yaw={start.yaw:g}"]
    return args


def _sim_overlay(scenario: Scenario, base: Path | None) -> dict[str, Any] | None:
    """sim2d parameters over config/sim2d.yaml: ``base``'s, plus a battery event's initial charge and the
    scenario's seed."""
    overlay: dict[str, Any] = yaml.safe_load(base.read_text(encoding="utf-8")) if base is not None else {}
    charges = [event.value for event in scenario.events if event.kind == "battery"]
    if charges:
        params = overlay.setdefault("sim2d", {}).setdefault("ros__parameters", {})
        params.setdefault("battery", {})["initial_charge"] = float(charges[-1])
    if scenario.seed is not None:
        overlay.setdefault("sim2d", {}).setdefault("ros__parameters", {})["seed"] = scenario.seed
    return overlay or None


def _machine_params(scenario: Scenario, mission: StateMachineMission, data_root: Path) -> dict[str, Any]:
    """config/<machine>.yaml with the scenario's parameters and start pose over it (floats where the
    file has floats: rclpy will not take 1 for a double parameter)."""
    node = MACHINES[mission.machine]
    path = data_root / "config" / f"{mission.machine}.yaml"
    document = yaml.safe_load(path.read_text(encoding="utf-8")) if path.exists() else {}
    params: dict[str, Any] = dict(document.get(node, {}).get("ros__parameters", {}))
    overrides = dict(mission.parameters)
    if scenario.start is not None:
        overrides["initial_pose"] = scenario.start.as_list()
    for name, value in overrides.items():
        if isinstance(value, list):
            value = [float(v) for v in value]
        elif isinstance(value, int) and not isinstance(value, bool) and isinstance(params.get(name), float):
            value = float(value)
        params[name] = value
    params["use_sim_time"] = True
    return {node: {"ros__parameters": params}}
