"""Field checks of the scenario file: each returns the clean value or raises a ``ScenarioError`` whose
message names the file, the scenario, the field and the bad value (and, where it helps, what is expected).

Kept apart from ``schema`` (the dataclasses and file structure) so the rules for one field read in one
place. Pure: yaml for the machines' parameter files, no ROS.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

import yaml

#: The reference machines a scenario may run, and their node (parameter file key) names.
MACHINES = {"sm_nav2_test_1": "SmNav2Test1", "sm_battery_patrol": "SmBatteryPatrol"}
#: Machines that count patrol rounds (``cycles``).
CYCLING_MACHINES = ("sm_battery_patrol",)
#: nav-bringup's --robot choices.
ROBOTS = ("waffle", "burger", "tb4")
#: The mission outcome words (see verdict.Outcome.result).
RESULTS = ("SUCCESS", "ABORT", "TIMEOUT", "STACK", "ERROR")
#: The processes a kill_<process> / freeze_<process> event may target. ``localization`` is a process of
#: its own only in nav-bringup's isolated layout, which a scenario with such an event runs in.
PROCESSES = ("navigation", "localization", "simulator")
KILL_EVENTS = tuple(f"kill_{process}" for process in PROCESSES)
FREEZE_EVENTS = tuple(f"freeze_{process}" for process in PROCESSES)
#: sim2d's robot outputs a topic_loss may silence (sim2d.core.disturbances.LOSABLE_TOPICS; a unit test
#: checks the two lists agree: ros_tools never imports sim2d)
LOSABLE_TOPICS = ("scan", "odom", "tf", "battery_state")
#: Every event kind the file may name. ``battery`` works at t = 0 only (sim2d's initial charge: sim2d
#: has no interface to set the charge of a running battery); the others are applied during the run by
#: the injector (navsuite_tools.scenarios.injector), each printing one "applied" line that the verdict counts.
INJECTED_EVENTS = ("kidnap", "lidar_dropout", "obstacle", "obstacle_on_path", "topic_loss", "odom_slip",
                   "clock_pause", *KILL_EVENTS, *FREEZE_EVENTS)
EVENT_KINDS = ("battery", *INJECTED_EVENTS)
#: The fields of the events whose value is a mapping, each with its check: "positive" (> 0), "scale"
#: (>= 0) or "topic" (one of LOSABLE_TOPICS).
EVENT_FIELDS = {"topic_loss": {"topic": "topic", "duration": "positive"},
                "odom_slip": {"scale": "scale", "duration": "positive"},
                "obstacle_on_path": {"ahead": "positive", "radius": "positive"}}
EXPECT_KEYS = ("result", "final_state", "tag", "result_code", "max_sim_time", "max_collisions",
               "max_localization_error", "min_clearance")
MISSION_KINDS = ("state_machine", "goals", "behavior_tree")
_NAME = re.compile(r"^[A-Za-z0-9_.-]+$")


class ScenarioError(ValueError):
    """A scenario file that cannot run as written; the message says where and why."""


@dataclass(frozen=True)
class FieldCheck:
    """Where a check happens: the file, the scenario's name (or index), the machines' config directory
    (None: parameter names and worlds are not checked) and the directory relative paths start from."""

    source: str
    scenario: str
    config_dir: Path | None
    base_dir: Path

    def fail(self, field: str, problem: str, value: object, expected: str = "") -> NoReturn:
        hint = f"; {expected}" if expected else ""
        where = f"{self.source}: scenario {self.scenario!r}: {field}"
        raise ScenarioError(f"{where}: {problem} (got {value!r}){hint}")


def check_name(check: FieldCheck, value: object) -> str:
    if not isinstance(value, str) or not _NAME.match(value):
        check.fail("name", "expected letters, digits, '_', '.' or '-'", value)
    return value


def check_number(check: FieldCheck, name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        check.fail(name, "expected a number", value)
    return float(value)


def check_positive(check: FieldCheck, name: str, value: object) -> float:
    number = check_number(check, name, value)
    if number <= 0.0:
        check.fail(name, "expected a number > 0", value)
    return number


def check_count(check: FieldCheck, name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        check.fail(name, f"expected an integer >= {minimum}", value)
    return value


def check_pose(check: FieldCheck, name: str, value: object) -> tuple[float, float, float]:
    """[x, y] or [x, y, yaw] (m, m, rad)."""
    if not isinstance(value, (list, tuple)) or len(value) not in (2, 3):
        check.fail(name, "expected [x, y, yaw] (m, m, rad)", value)
    numbers = [check_number(check, f"{name}[{i}]", v) for i, v in enumerate(value)]
    return (numbers[0], numbers[1], numbers[2] if len(numbers) == 3 else 0.0)


def check_world(check: FieldCheck, value: object) -> str:
    """A sim2d world name (its map is maps/<world>.yaml) or a world YAML path."""
    if not isinstance(value, str) or not value:
        check.fail("world", "expected a world name", value)
    if check.config_dir is not None and not value.endswith(".yaml"):
        maps = check.config_dir.parent / "maps"
        if not (maps / f"{value}.yaml").exists():
            known = sorted(p.stem for p in maps.glob("*.yaml"))
            check.fail("world", "unknown world", value, f"expected one of {', '.join(known)}")
    return value


def check_robot(check: FieldCheck, value: object) -> str:
    if value not in ROBOTS:
        check.fail("robot", "unknown robot", value, f"expected one of {', '.join(ROBOTS)}")
    return str(value)


def check_file(check: FieldCheck, name: str, value: object) -> Path:
    """An existing file: absolute, else relative to the scenario file, else to the folder holding the
    shipped config/ (the repository root in a checkout; ``config_dir``'s parent)."""
    if not isinstance(value, str) or not value:
        check.fail(name, "expected a file path", value)
    path = Path(value)
    candidates = [path] if path.is_absolute() else [check.base_dir / path]
    if check.config_dir is not None and not path.is_absolute():
        candidates.append(check.config_dir.parent / path)
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
    check.fail(name, "no such file", value, "looked at " + " and ".join(str(c) for c in candidates))


def check_params(check: FieldCheck, value: object) -> tuple[Path, ...]:
    """Nav2 parameter files for nav-bringup's ``--params``, in order (later files win): a path or a
    list of paths, each resolved as ``check_file`` does. They replace the robot's default file, as
    ``--params`` does, so a scenario that adds a section names the base file first."""
    files = [value] if isinstance(value, str) else value
    if not isinstance(files, list) or not files:
        check.fail("params", "expected a parameter file or a non-empty list of them", value)
    return tuple(check_file(check, f"params[{i}]", item) for i, item in enumerate(files))


def check_mission(check: FieldCheck, value: object) -> tuple[str, dict[str, Any]]:
    """Exactly one of state_machine, goals, behavior_tree, and the keys that go with it."""
    if not isinstance(value, dict):
        check.fail("mission", "expected a mapping", value, f"with one of {', '.join(MISSION_KINDS)}")
    kinds = [kind for kind in MISSION_KINDS if kind in value]
    if len(kinds) != 1:
        check.fail("mission", "expected exactly one of " + ", ".join(MISSION_KINDS), sorted(value))
    kind = kinds[0]
    allowed = {"state_machine": ("state_machine", "parameters", "cycles"),
               "goals": ("goals", "max_goal_time"),
               "behavior_tree": ("behavior_tree", "locations", "max_cycles")}[kind]
    for key in value:
        if key not in allowed:
            check.fail(f"mission.{key}", f"not a field of a {kind} mission", value[key],
                       f"expected {', '.join(allowed)}")
    if kind == "goals":
        goals = value["goals"]
        if not isinstance(goals, list) or not goals:
            check.fail("mission.goals", "expected a non-empty list of [x, y, yaw]", goals)
        limit = value.get("max_goal_time")
        if limit is not None:
            limit = check_positive(check, "mission.max_goal_time", limit)
        return kind, {"goals": [check_pose(check, f"mission.goals[{i}]", g) for i, g in enumerate(goals)],
                      "max_goal_time": limit}
    if kind == "behavior_tree":
        return kind, {"tree": check_file(check, "mission.behavior_tree", value["behavior_tree"]),
                      "locations": check_file(check, "mission.locations",
                                              value.get("locations", "config/locations.yaml")),
                      "max_cycles": check_count(check, "mission.max_cycles", value.get("max_cycles", 1), 1)}
    return kind, _state_machine(check, value)


def _state_machine(check: FieldCheck, value: dict[str, Any]) -> dict[str, Any]:
    machine = value["state_machine"]
    if machine not in MACHINES:
        check.fail("mission.state_machine", "unknown state machine", machine,
                   f"expected one of {', '.join(MACHINES)}")
    parameters = value.get("parameters") or {}
    if not isinstance(parameters, dict):
        check.fail("mission.parameters", "expected a mapping of parameter names to values", parameters)
    known = _machine_parameters(check, machine)
    for key, item in parameters.items():
        where = f"mission.parameters.{key}"
        if key == "initial_pose":
            check.fail(where, "set by the scenario's start", item, "give start: [x, y, yaw] instead")
        if known is not None and key not in known:
            check.fail(where, f"not a parameter of {machine}", item,
                       f"expected one of {', '.join(sorted(known))}")
        if isinstance(item, list):
            check_pose(check, where, item)
        elif not isinstance(item, (int, float, str, bool)):
            check.fail(where, "expected a number, string, boolean or [x, y, yaw]", item)
    cycles = value.get("cycles")
    if cycles is not None:
        if machine not in CYCLING_MACHINES:
            check.fail("mission.cycles", f"{machine} has no patrol rounds", cycles)
        cycles = check_count(check, "mission.cycles", cycles, 1)
    return {"machine": machine, "parameters": dict(parameters), "cycles": cycles}


def _machine_parameters(check: FieldCheck, machine: str) -> set[str] | None:
    """The parameter names in config/<machine>.yaml, or None when there is no config directory."""
    if check.config_dir is None:
        return None
    path = check.config_dir / f"{machine}.yaml"
    document: Any = yaml.safe_load(path.read_text(encoding="utf-8")) if path.exists() else None
    try:
        return set(document[MACHINES[machine]]["ros__parameters"])
    except (TypeError, KeyError):
        return None


def check_events(check: FieldCheck, value: object) -> list[tuple[float, str, Any]]:
    """``[{at: s, <kind>: value}, ...]`` → (at, kind, value) sorted by time; unsupported kinds fail here."""
    if not isinstance(value, list):
        check.fail("events", "expected a list of {at: s, <kind>: value}", value)
    events = []
    for index, entry in enumerate(value):
        where = f"events[{index}]"
        if not isinstance(entry, dict) or "at" not in entry or len(entry) != 2:
            check.fail(where, "expected {at: <sim s>, <kind>: <value>}", entry,
                       f"kinds: {', '.join(EVENT_KINDS)}")
        at = check_number(check, f"{where}.at", entry["at"])
        if at < 0.0:
            check.fail(f"{where}.at", "expected sim seconds >= 0", entry["at"])
        kind = next(key for key in entry if key != "at")
        events.append((at, kind, _event_value(check, f"{where}.{kind}", kind, entry[kind], at)))
    return sorted(events, key=lambda event: event[0])


def _event_value(check: FieldCheck, where: str, kind: str, value: object, at: float) -> Any:
    if kind not in EVENT_KINDS:
        check.fail(where, "unknown event", kind, f"expected one of {', '.join(EVENT_KINDS)}")
    if kind == "kidnap":
        return check_pose(check, where, value)
    if kind == "battery":
        charge = check_number(check, where, value)
        if not 0.0 <= charge <= 1.0:
            check.fail(where, "expected a charge fraction in 0..1", value)
        if at != 0.0:
            check.fail(where, "not yet supported after t = 0 (sim2d sets only the initial charge)", value)
        return charge
    if kind == "lidar_dropout":
        return check_positive(check, where, value)
    if kind == "obstacle":
        if not (isinstance(value, list) and len(value) == 3):
            check.fail(where, "expected [x, y, radius] (m, map frame)", value)
        x, y = (check_number(check, f"{where}[{i}]", v) for i, v in enumerate(value[:2]))
        return (x, y, check_positive(check, f"{where}[2]", value[2]))
    if kind in FREEZE_EVENTS or kind == "clock_pause":  # wall s: a frozen process or clock stops sim time
        return check_positive(check, where, value)
    if kind in EVENT_FIELDS:
        return _event_fields(check, where, kind, value)
    if value not in (None, True):  # kill_<process>
        check.fail(where, "takes no value", value, f"write {{at: <sim s>, {kind}: null}}")
    return None


def _event_fields(check: FieldCheck, where: str, kind: str, value: object) -> dict[str, Any]:
    """A mapping event (EVENT_FIELDS): every field present, each checked."""
    fields = EVENT_FIELDS[kind]
    shape = "{" + ", ".join(fields) + "}"
    if not isinstance(value, dict) or set(value) != set(fields):
        check.fail(where, f"expected {shape}", value)
    clean: dict[str, Any] = {}
    for name, rule in fields.items():
        item = value[name]
        if rule == "topic":
            if item not in LOSABLE_TOPICS:
                check.fail(f"{where}.{name}", "unknown topic", item,
                           f"expected one of {', '.join(LOSABLE_TOPICS)}")
            clean[name] = item
        elif rule == "scale":
            clean[name] = check_number(check, f"{where}.{name}", item)
            if clean[name] < 0.0:
                check.fail(f"{where}.{name}", "expected a scale >= 0 (1: no slip)", item)
        else:
            clean[name] = check_positive(check, f"{where}.{name}", item)
    return clean


def check_expect(check: FieldCheck, value: object) -> dict[str, Any]:
    """The pass criteria (see schema.Expect); an absent key keeps Expect's default."""
    if not isinstance(value, dict):
        check.fail("expect", "expected a mapping", value, f"keys: {', '.join(EXPECT_KEYS)}")
    clean: dict[str, Any] = {}
    for key, item in value.items():
        where = f"expect.{key}"
        if key not in EXPECT_KEYS:
            check.fail(where, "unknown criterion", item, f"expected one of {', '.join(EXPECT_KEYS)}")
        if item is None:
            clean[key] = None
        elif key == "result":
            if item not in RESULTS:
                check.fail(where, "unknown result", item, f"expected one of {', '.join(RESULTS)}")
            clean[key] = item
        elif key in ("final_state", "tag"):
            if not isinstance(item, str) or not item:
                check.fail(where, "expected a name", item)
            clean[key] = item
        elif key == "result_code" or key == "max_collisions":
            clean[key] = check_count(check, where, item, 0)
        elif key == "min_clearance":
            clean[key] = check_number(check, where, item)
            if clean[key] < 0.0:
                check.fail(where, "expected a distance >= 0 (m)", item)
        else:
            clean[key] = check_positive(check, where, item)
    return clean
