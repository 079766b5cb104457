"""The scenario file: what one mission run is (world, robot, start, mission, events) and how it is judged.

Pure (yaml + stdlib): ``load_scenarios(path)`` parses and validates the whole file before anything
runs, so a typo fails at once with the file, the scenario, the field and the bad value in the message
(``ScenarioError``), not as a mission that silently drives somewhere else. The field-level checks live
in ``schema_fields``; this module holds the dataclasses and the file-level structure (defaults, sweeps,
unique names).

File layout (units: m, rad, sim s for ``at``/``max_sim_time``, wall s for ``timeout``)::

    defaults: {world: turtlebot3_world, robot: waffle, timeout: 120}   # merged into every scenario
    scenarios:
      - name: seed_nominal
        start: [-2.0, -0.5, 0.0]                     # x, y, yaw in the map frame
        mission: {state_machine: sm_nav2_test_1, parameters: {waypoint_1: [2.0, 0.0, 0.0]}}
        # or {goals: [[x, y, yaw], ...], max_goal_time: 20} (sim s, then the goal is canceled)
        params: [config/nav2_params.yaml, my_overlay.yaml]  # nav-bringup --params (replace the robot's)
        events: [{at: 8.0, kidnap: [0.5, -1.6, 0.0]}, {at: 12.0, lidar_dropout: 3.0},
                 {at: 15.0, obstacle: [0.5, 0.0, 0.15]}, {at: 30.0, kill_navigation: null}]
        # also: {obstacle_on_path: {ahead: 1.0, radius: 0.15}} (m along the current /plan),
        # {topic_loss: {topic: scan, duration: 2.0}} (sim s; scan, odom, tf or battery_state),
        # {odom_slip: {scale: 1.3, duration: 5.0}}, {clock_pause: 3.0} (wall s),
        # {kill_<process>: null}, {freeze_<process>: 3.0} (SIGSTOP for wall s, then SIGCONT), where
        # <process> is navigation, localization (runs the stack in its isolated layout) or simulator
        seed: 3                                      # sim2d's random streams (lidar noise, odometry drift)
        expect: {result: SUCCESS, final_state: StFinalState, max_sim_time: 90, max_collisions: 0,
                 min_clearance: 0.05}
        sweep: {start: [[-2.0, -0.5, 0.0], [-2.0, 0.5, 0.0]]}   # one scenario per start, name-1, name-2…
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import yaml

from navsuite_tools.scenarios.schema_fields import (
    FieldCheck,
    ScenarioError,
    check_count,
    check_events,
    check_expect,
    check_mission,
    check_name,
    check_params,
    check_pose,
    check_positive,
    check_robot,
    check_world,
)

#: Keys a scenario (or ``defaults``) may have; anything else is a typo and fails the load.
SCENARIO_KEYS = ("name", "world", "robot", "start", "mission", "params", "events", "expect", "timeout",
                 "sweep", "seed")
DEFAULT_TIMEOUT = 180.0  # wall s the mission may take (its command's --timeout); the farm adds a margin
__all__ = ["BehaviorTreeMission", "Event", "Expect", "GoalsMission", "Pose2D", "Scenario", "ScenarioError",
           "StateMachineMission", "load_scenarios", "parse_scenarios"]


@dataclass(frozen=True)
class Pose2D:
    """A pose in the map frame: x, y (m), yaw (rad)."""

    x: float
    y: float
    yaw: float = 0.0

    def as_list(self) -> list[float]:
        return [self.x, self.y, self.yaw]


@dataclass(frozen=True)
class StateMachineMission:
    """A reference state machine by name, with node parameters (over config/<name>.yaml) and, for the
    patrol, the rounds to complete."""

    machine: str
    parameters: Mapping[str, Any] = field(default_factory=dict)
    cycles: int | None = None


@dataclass(frozen=True)
class GoalsMission:
    """NavigateToPose goals sent one after the other; the run stops at the first that fails.
    ``max_goal_time``: sim s after which a running goal is canceled (None: never)."""

    goals: tuple[Pose2D, ...]
    max_goal_time: float | None = None


@dataclass(frozen=True)
class BehaviorTreeMission:
    """nav-autonomy's behavior tree over a locations file, for ``max_cycles`` root results."""

    tree: Path
    locations: Path
    max_cycles: int = 1


Mission = StateMachineMission | GoalsMission | BehaviorTreeMission


@dataclass(frozen=True)
class Event:
    """Something done to the world at sim time ``at`` (s since the simulator's first step).

    ``kind`` is one of schema_fields.EVENT_KINDS; ``value`` is a Pose2D (kidnap), a charge fraction 0..1
    (battery), a duration in sim s (lidar_dropout), (x, y, radius) m in the map frame (obstacle), a
    mapping of the fields in schema_fields.EVENT_FIELDS (obstacle_on_path, topic_loss, odom_slip), a
    duration in wall s (freeze_<process>, clock_pause: sim time stands still meanwhile, so it cannot
    measure them) or None (kill_<process>: SIGKILL; kill_navigation hits the process running
    bt_navigator and the controller).
    """

    at: float
    kind: str
    value: Any = None


@dataclass(frozen=True)
class Expect:
    """Pass criteria; None means not checked. Checked in this order, the first failing one is named.

    result: the mission's outcome word (SUCCESS, ABORT, TIMEOUT, STACK).
    final_state / tag: the state the machine ended in, the tag (family) of its last transition.
    result_code: the Nav2 error code of the last navigation result (0 on success).
    max_sim_time: s of sim time the mission may take.
    max_collisions: contacts sim2d may report (zero collisions by default).
    max_localization_error: m between AMCL's pose and the truth, at any time of the run.
    min_clearance: m the robot's body must keep from every obstacle at all times (sim2d's ground-truth
        /sim2d/clearance, recorded; the smallest value of the run).
    """

    result: str | None = "SUCCESS"
    final_state: str | None = None
    tag: str | None = None
    result_code: int | None = None
    max_sim_time: float | None = None
    max_collisions: int | None = 0
    max_localization_error: float | None = None
    min_clearance: float | None = None


@dataclass(frozen=True)
class Scenario:
    """One mission run. ``source`` is the file it came from (for messages and reports); ``params`` the
    Nav2 parameter files given to nav-bringup (empty: the robot's default)."""

    name: str
    world: str
    robot: str
    start: Pose2D | None
    mission: Mission
    events: tuple[Event, ...] = ()
    expect: Expect = Expect()
    timeout: float = DEFAULT_TIMEOUT
    source: str = ""
    params: tuple[Path, ...] = ()
    seed: int | None = None

    @property
    def isolated(self) -> bool:
        """Whether the stack must run in nav-bringup's isolated layout (an event targets localization)."""
        return any(event.kind.endswith("_localization") for event in self.events)


def load_scenarios(path: str | Path, config_dir: Path | None = None) -> list[Scenario]:
    """Read and validate a scenario file; ``config_dir`` holds config/<machine>.yaml (parameter names)."""
    path = Path(path)
    try:
        document = yaml.safe_load(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise ScenarioError(f"{path}: cannot read: {error.strerror}") from error
    except yaml.YAMLError as error:
        raise ScenarioError(f"{path}: not valid YAML: {error}") from error
    return parse_scenarios(document, str(path), config_dir, base_dir=path.parent)


def parse_scenarios(document: object, source: str, config_dir: Path | None = None,
                    base_dir: Path | None = None) -> list[Scenario]:
    """Validate a parsed document (see the module doc); relative file paths resolve against ``base_dir``."""
    if not isinstance(document, dict) or not isinstance(document.get("scenarios"), list):
        raise ScenarioError(f"{source}: expected a mapping with a 'scenarios' list")
    unknown = set(document) - {"defaults", "scenarios"}
    if unknown:
        raise ScenarioError(f"{source}: unknown top-level key {sorted(unknown)[0]!r} "
                            "(expected defaults, scenarios)")
    defaults = document.get("defaults") or {}
    if not isinstance(defaults, dict):
        raise ScenarioError(f"{source}: defaults: expected a mapping, got {defaults!r}")
    scenarios: list[Scenario] = []
    for index, entry in enumerate(document["scenarios"]):
        if not isinstance(entry, dict):
            raise ScenarioError(f"{source}: scenarios[{index}]: expected a mapping, got {entry!r}")
        merged = {**defaults, **entry}
        label = str(merged.get("name", f"#{index}"))
        check = FieldCheck(source, label, config_dir, base_dir or Path("."))
        scenarios.extend(_expand(check, merged))
    seen: set[str] = set()
    for scenario in scenarios:
        if scenario.name in seen:
            raise ScenarioError(f"{source}: scenario {scenario.name!r}: name: used twice")
        seen.add(scenario.name)
    return scenarios


def _expand(check: FieldCheck, raw: dict[str, Any]) -> list[Scenario]:
    """One scenario, or one per start pose of its ``sweep``."""
    unknown = [key for key in raw if key not in SCENARIO_KEYS]
    if unknown:
        check.fail(unknown[0], "unknown field", raw[unknown[0]],
                   f"expected one of {', '.join(SCENARIO_KEYS)}")
    scenario = _scenario(check, raw)
    sweep = raw.get("sweep")
    if sweep is None:
        return [scenario]
    if not isinstance(sweep, dict) or set(sweep) != {"start"} or not isinstance(sweep["start"], list) \
            or not sweep["start"]:
        check.fail("sweep", "expected {start: [[x, y, yaw], ...]}", sweep)
    starts = [Pose2D(*check_pose(check, f"sweep.start[{i}]", pose)) for i, pose in enumerate(sweep["start"])]
    return [replace(scenario, name=f"{scenario.name}-{i + 1}", start=start) for i, start in enumerate(starts)]


def _scenario(check: FieldCheck, raw: dict[str, Any]) -> Scenario:
    name = check_name(check, raw.get("name"))
    start = None if raw.get("start") is None else Pose2D(*check_pose(check, "start", raw["start"]))
    if "mission" not in raw:
        check.fail("mission", "missing", None, "state_machine, goals or behavior_tree")
    kind, values = check_mission(check, raw["mission"])
    mission: Mission
    if kind == "state_machine":
        mission = StateMachineMission(values["machine"], values["parameters"], values["cycles"])
    elif kind == "goals":
        mission = GoalsMission(tuple(Pose2D(*pose) for pose in values["goals"]), values["max_goal_time"])
    else:
        mission = BehaviorTreeMission(values["tree"], values["locations"], values["max_cycles"])
    events = tuple(Event(at, kind_, Pose2D(*value) if kind_ == "kidnap" else value)
                   for at, kind_, value in check_events(check, raw.get("events") or []))
    expect = Expect(**check_expect(check, raw.get("expect") or {}))
    timeout = check_positive(check, "timeout", raw.get("timeout", DEFAULT_TIMEOUT))
    params = () if raw.get("params") is None else check_params(check, raw["params"])
    seed = None if raw.get("seed") is None else check_count(check, "seed", raw["seed"], 0)
    return Scenario(name, check_world(check, raw.get("world", "turtlebot3_world")),
                    check_robot(check, raw.get("robot", "waffle")), start, mission, events, expect, timeout,
                    check.source, params, seed)
