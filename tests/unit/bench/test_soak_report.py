"""The soak benchmark's pure parts: its plan, how failures are classified, what it counts."""

from __future__ import annotations

import pytest

from bench.nav_driver import GoalOutcome
from bench.nav_session import GoalRecord
from bench.soak_report import Config, ConfigResult, Tally, parse_plan, split_goals


def _record(index: int, outcome: GoalOutcome, wall_s: float = 2.0) -> GoalRecord:
    return GoalRecord(index, (0.0, 0.0, 0.0), outcome, 10.0, outcome.sim_s, 0, wall_s, 0, 0.0, 1.0)


def test_parse_plan_reads_world_robot_goals_items() -> None:
    assert parse_plan("turtlebot3_house:waffle:3, depot_large:tb4:2") == [
        Config("turtlebot3_house", "waffle", 3), Config("depot_large", "tb4", 2)]


@pytest.mark.parametrize(("plan", "says"), [
    ("turtlebot3_house:waffle", "is not world:robot:goals"),
    ("nowhere:waffle:3", "no world 'nowhere'"),
    ("turtlebot3_house:roomba:3", "unknown robot 'roomba'"),
    ("turtlebot3_house:waffle:0", "positive integer"),
    ("turtlebot3_house:waffle:x", "positive integer"),
])
def test_parse_plan_names_what_is_wrong(plan: str, says: str) -> None:
    with pytest.raises(ValueError, match=says):
        parse_plan(plan)


def test_split_goals_spreads_the_rest_over_the_first_configurations() -> None:
    assert split_goals(200, 4) == [50, 50, 50, 50]
    assert split_goals(6, 4) == [2, 2, 1, 1]


def test_a_failure_is_explained_only_with_an_error_code_and_a_message() -> None:
    assert GoalOutcome(False, 5.0, 104, "no valid path").explained
    assert not GoalOutcome(False, 5.0, 0, "aborted").explained
    assert not GoalOutcome(False, 5.0, 104, "  ").explained
    assert not GoalOutcome(False, 5.0, None, "timeout").explained
    assert not GoalOutcome(True, 5.0, 0, "").explained


def test_goals_a_failed_configuration_never_drove_count_as_unexplained() -> None:
    result = ConfigResult(Config("office_small", "tb4", 5), error="RuntimeError: stack died")
    result.records += [_record(1, GoalOutcome(True, 12.0, 0, "")),
                       _record(2, GoalOutcome(False, 3.0, 104, "no valid path"))]
    assert (result.goals, result.successes, result.explained, result.unexplained) == (5, 1, 1, 3)


def test_an_interrupted_configuration_counts_only_the_goals_it_drove() -> None:
    result = ConfigResult(Config("office_small", "tb4", 5))
    result.records += [_record(1, GoalOutcome(True, 12.0, 0, "")),
                       _record(2, GoalOutcome(False, 0.0, None, ""))]
    assert (result.goals, result.unexplained) == (2, 1)


def test_the_total_sums_configurations_and_keeps_the_lowest_battery() -> None:
    first = ConfigResult(Config("turtlebot3_world", "waffle", 2), collisions=1, battery=0.9)
    first.records += [_record(1, GoalOutcome(True, 12.0, 0, "")), _record(2, GoalOutcome(True, 14.0, 0, ""))]
    second = ConfigResult(Config("depot_large", "tb4", 1), battery=0.7)
    second.records.append(_record(1, GoalOutcome(False, 0.0, None, "goal not accepted"), wall_s=0.0))
    total = Tally.of([first, second])
    assert (total.goals, total.successes, total.collisions, total.unexplained) == (3, 2, 1, 1)
    assert total.battery == pytest.approx(70.0)
    assert total.success_rate == pytest.approx(200.0 / 3)
    assert total.ratio_median == pytest.approx(1.3)  # 12 s and 14 s over a 10 s ideal
    assert total.wall_median == pytest.approx(2.0)  # the goal never accepted has no wall time
