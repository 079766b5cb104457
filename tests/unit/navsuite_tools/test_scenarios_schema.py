"""The scenario file's validation: valid files load into dataclasses, and every bad field fails at load
with the file, the scenario, the field and the bad value in the message. No ROS."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from navsuite_tools.scenarios.schema import (
    BehaviorTreeMission,
    GoalsMission,
    Pose2D,
    ScenarioError,
    StateMachineMission,
    load_scenarios,
    parse_scenarios,
)

REPO = Path(__file__).resolve().parents[3]
CONFIG = REPO / "config"
SHIPPED = REPO / "config" / "scenarios" / "seed_missions.yaml"


def _one(**fields: Any) -> dict[str, Any]:
    scenario = {"name": "s1", "mission": {"state_machine": "sm_nav2_test_1"}, **fields}
    return {"scenarios": [scenario]}


def _error(document: dict[str, Any]) -> str:
    with pytest.raises(ScenarioError) as info:
        parse_scenarios(document, "file.yaml", CONFIG, REPO)
    return str(info.value)


def test_the_shipped_file_is_valid_and_has_twenty_scenarios_or_more() -> None:
    scenarios = load_scenarios(SHIPPED, CONFIG)
    assert len(scenarios) >= 20
    kinds = {type(s.mission) for s in scenarios}
    assert kinds == {StateMachineMission, GoalsMission, BehaviorTreeMission}
    assert len({s.name for s in scenarios}) == len(scenarios)


def test_defaults_are_merged_and_a_scenario_overrides_them() -> None:
    document = {"defaults": {"robot": "burger", "timeout": 30},
                "scenarios": [{"name": "a", "mission": {"goals": [[1, 2]]}},
                              {"name": "b", "robot": "tb4", "mission": {"goals": [[1, 2, 3]]}}]}
    a, b = parse_scenarios(document, "f.yaml", CONFIG, REPO)
    assert (a.robot, a.timeout, b.robot) == ("burger", 30.0, "tb4")
    assert a.mission == GoalsMission((Pose2D(1.0, 2.0, 0.0),))
    assert a.world == "turtlebot3_world" and a.start is None


def test_a_sweep_expands_into_one_named_scenario_per_start() -> None:
    document = _one(sweep={"start": [[0, 0, 0], [1, 1, 1.5]]})
    runs = parse_scenarios(document, "f.yaml", CONFIG, REPO)
    assert [(s.name, s.start) for s in runs] == [("s1-1", Pose2D(0, 0, 0)), ("s1-2", Pose2D(1, 1, 1.5))]


def test_events_are_parsed_and_sorted_by_sim_time() -> None:
    document = _one(events=[{"at": 9, "kidnap": [1, 2, 0]}, {"at": 0, "battery": 0.5}])
    (scenario,) = parse_scenarios(document, "f.yaml", CONFIG, REPO)
    assert [(e.at, e.kind, e.value) for e in scenario.events] == [(0.0, "battery", 0.5),
                                                                   (9.0, "kidnap", Pose2D(1, 2, 0))]


def test_machine_parameters_and_cycles_are_kept() -> None:
    document = {"scenarios": [{"name": "p", "mission": {"state_machine": "sm_battery_patrol", "cycles": 2,
                                                         "parameters": {"low_threshold": 0.5}}}]}
    (scenario,) = parse_scenarios(document, "f.yaml", CONFIG, REPO)
    assert scenario.mission == StateMachineMission("sm_battery_patrol", {"low_threshold": 0.5}, 2)


def test_a_behavior_tree_path_resolves_against_the_repository() -> None:
    tree = "config/trees/seed_battery_patrol_v3.xml"
    document = {"scenarios": [{"name": "t", "mission": {"behavior_tree": tree}}]}
    (scenario,) = parse_scenarios(document, "f.yaml", CONFIG, Path("/nonexistent"))
    assert isinstance(scenario.mission, BehaviorTreeMission)
    assert scenario.mission.tree == REPO / "config" / "trees" / "seed_battery_patrol_v3.xml"
    assert scenario.mission.locations == REPO / "config" / "locations.yaml"


@pytest.mark.parametrize(("fields", "field", "value"), [
    ({"robot": "roomba"}, "robot", "'roomba'"),
    ({"world": "atlantis"}, "world", "'atlantis'"),
    ({"start": [1, "x", 0]}, "start[1]", "'x'"),
    ({"start": [1]}, "start", "[1]"),
    ({"timeout": -5}, "timeout", "-5"),
    ({"colour": "red"}, "colour", "'red'"),
    ({"expect": {"max_sim_time": 0}}, "expect.max_sim_time", "0"),
    ({"expect": {"result": "WIN"}}, "expect.result", "'WIN'"),
    ({"expect": {"max_collision": 0}}, "expect.max_collision", "0"),
    ({"expect": {"max_collisions": -1}}, "expect.max_collisions", "-1"),
    ({"events": [{"at": -1, "kidnap": [0, 0, 0]}]}, "events[0].at", "-1"),
    ({"events": [{"at": 1, "teleport": [0, 0, 0]}]}, "events[0].teleport", "'teleport'"),
    ({"events": [{"at": 0, "battery": 1.5}]}, "events[0].battery", "1.5"),
    ({"events": [{"at": 3, "battery": 0.5}]}, "events[0].battery", "0.5"),
    ({"mission": {"state_machine": "sm_nope"}}, "mission.state_machine", "'sm_nope'"),
    ({"mission": {"state_machine": "sm_nav2_test_1", "parameters": {"waypoint1": [1, 1, 0]}}},
     "mission.parameters.waypoint1", "[1, 1, 0]"),
    ({"mission": {"state_machine": "sm_nav2_test_1", "parameters": {"initial_pose": [1, 1, 0]}}},
     "mission.parameters.initial_pose", "[1, 1, 0]"),
    ({"mission": {"state_machine": "sm_nav2_test_1", "cycles": 2}}, "mission.cycles", "2"),
    ({"mission": {"goals": []}}, "mission.goals", "[]"),
    ({"mission": {"goals": [[0, 0]], "state_machine": "sm_nav2_test_1"}}, "mission",
     "['goals', 'state_machine']"),
    ({"mission": {"behavior_tree": "no/such/tree.xml"}}, "mission.behavior_tree", "'no/such/tree.xml'"),
])
def test_a_bad_field_names_the_file_the_scenario_the_field_and_the_value(
        fields: dict[str, Any], field: str, value: str) -> None:
    message = _error(_one(**fields))
    assert message.startswith(f"file.yaml: scenario 's1': {field}: "), message
    assert f"(got {value})" in message


def test_injected_events_load_with_their_values() -> None:
    events = [{"at": 5, "lidar_dropout": 3}, {"at": 6, "obstacle": [0.5, -1, 0.15]},
              {"at": 9, "kill_navigation": None}]
    scenario = parse_scenarios(_one(events=events), "file.yaml")[0]
    assert [(e.at, e.kind, e.value) for e in scenario.events] == [
        (5.0, "lidar_dropout", 3.0), (6.0, "obstacle", (0.5, -1.0, 0.15)), (9.0, "kill_navigation", None)]


@pytest.mark.parametrize(("event", "field", "value"), [
    ({"lidar_dropout": 0}, "lidar_dropout", "0"),
    ({"obstacle": [0.5, 0.5]}, "obstacle", "[0.5, 0.5]"),
    ({"obstacle": [0.5, 0.5, -0.1]}, "obstacle[2]", "-0.1"),
    ({"kill_navigation": "nav2"}, "kill_navigation", "'nav2'"),
])
def test_a_bad_injected_event_names_its_field_and_value(event: dict[str, Any], field: str,
                                                        value: str) -> None:
    message = _error(_one(events=[{"at": 5, **event}]))
    assert f"events[0].{field}: " in message and f"(got {value})" in message, message


def test_a_duplicate_name_fails_naming_it() -> None:
    document = {"scenarios": [_one()["scenarios"][0], _one()["scenarios"][0]]}
    assert _error(document) == "file.yaml: scenario 's1': name: used twice"


def test_a_sweep_name_colliding_with_another_scenario_fails() -> None:
    document = {"scenarios": [{**_one()["scenarios"][0], "sweep": {"start": [[0, 0]]}},
                              {"name": "s1-1", "mission": {"goals": [[0, 0]]}}]}
    assert "scenario 's1-1': name: used twice" in _error(document)


def test_a_file_that_is_not_yaml_names_the_file(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("scenarios: [\n")
    with pytest.raises(ScenarioError, match=r"bad\.yaml: not valid YAML"):
        load_scenarios(path, CONFIG)


def test_a_missing_file_names_the_file(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"nothere\.yaml: cannot read"):
        load_scenarios(tmp_path / "nothere.yaml", CONFIG)


def test_a_file_without_a_scenarios_list_is_rejected(tmp_path: Path) -> None:
    path = tmp_path / "empty.yaml"
    path.write_text(yaml.safe_dump({"defaults": {}}))
    with pytest.raises(ScenarioError, match="expected a mapping with a 'scenarios' list"):
        load_scenarios(path, CONFIG)


def test_min_clearance_and_parameter_files_load_and_the_shipped_collision_monitor_file_is_valid() -> None:
    document = _one(expect={"min_clearance": 0.05, "max_collisions": 0},
                    params=["config/nav2_params.yaml", "config/scenarios/collision_monitor_params.yaml"])
    (scenario,) = parse_scenarios(document, "file.yaml", CONFIG, REPO)
    assert scenario.expect.min_clearance == 0.05
    overlay = CONFIG / "scenarios" / "collision_monitor_params.yaml"
    assert scenario.params == (CONFIG / "nav2_params.yaml", overlay)
    (single,) = parse_scenarios(_one(params="config/nav2_params.yaml"), "file.yaml", CONFIG, REPO)
    assert single.params == (CONFIG / "nav2_params.yaml",)
    assert parse_scenarios(_one(), "file.yaml", CONFIG, REPO)[0].params == ()  # the robot's default
    (shipped,) = load_scenarios(CONFIG / "scenarios" / "collision_monitor.yaml", CONFIG)
    assert shipped.expect.min_clearance == 0.05 and shipped.expect.max_collisions == 0
    assert [e.kind for e in shipped.events] == ["obstacle"]
    assert shipped.params[-1].name == "collision_monitor_params.yaml"


@pytest.mark.parametrize(("fields", "field", "value"), [
    ({"expect": {"min_clearance": -0.01}}, "expect.min_clearance", "-0.01"),
    ({"expect": {"min_clearance": "5 cm"}}, "expect.min_clearance", "'5 cm'"),
    ({"params": []}, "params", "[]"),
    ({"params": ["config/no_such_params.yaml"]}, "params[0]", "'config/no_such_params.yaml'"),
])
def test_a_bad_clearance_bound_or_parameter_file_names_its_field_and_value(
        fields: dict[str, Any], field: str, value: str) -> None:
    message = _error(_one(**fields))
    assert message.startswith(f"file.yaml: scenario 's1': {field}: "), message
    assert f"(got {value})" in message


def test_a_goal_list_may_limit_each_goal_s_sim_time() -> None:
    document = _one(mission={"goals": [[1, 2]], "max_goal_time": 20})
    (limited,) = parse_scenarios(document, "f.yaml", CONFIG, REPO)
    assert limited.mission == GoalsMission((Pose2D(1.0, 2.0, 0.0),), 20.0)
    message = _error(_one(mission={"goals": [[1, 2]], "max_goal_time": 0}))
    assert "mission.max_goal_time: expected a number > 0 (got 0)" in message
    message = _error(_one(mission={"state_machine": "sm_nav2_test_1", "max_goal_time": 5}))
    assert "mission.max_goal_time: not a field of a state_machine mission" in message
