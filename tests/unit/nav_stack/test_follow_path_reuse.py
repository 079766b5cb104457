"""The rest of the current path (nav_stack/core/control/follow_path.py): is_remainder and what a
preempting goal keeps (PathFollowing.take_over).

The bt_navigator replans every second and sends each plan as a new FollowPath goal (issue 44): when
the plan is the same route toward the same goal from where the robot now is, only the path array
changes; another path toward another goal restarts the goal checker, another controller everything.
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.control import SimpleGoalChecker
from nav_stack.core.control.follow_path import PathFollowing, Plugins, Takeover, is_remainder

STEP = 0.03  # m between poses, a 3 cm map's cells
TOLERANCE = 0.1  # m
IDS = ("FollowPath", "general_goal_checker", "progress_checker")


def route() -> np.ndarray:
    """An L: 6 m along +x, then 4 m along +y, yaw facing along; the goal faces +y."""
    east = np.column_stack((np.arange(0.0, 6.0, STEP), np.zeros(200), np.zeros(200)))
    north = np.column_stack((np.full(134, 6.0), np.arange(0.0, 4.0, STEP)[:134], np.full(134, math.pi / 2)))
    return np.vstack((east, north))


def rest_from(path: np.ndarray, index: int, robot_offset: float = 0.0) -> np.ndarray:
    """What a planner returns from a robot near pose ``index``: the same cells from there on, its
    first pose the robot's own (``robot_offset`` m beside the path)."""
    rest = path[index:].copy()
    rest[0, 1] += robot_offset
    return rest


class Counting:
    """A plugin that counts its resets."""

    def __init__(self) -> None:
        self.resets = 0

    def reset(self) -> None:
        self.resets += 1


def test_the_same_route_from_where_the_robot_is_now_is_the_remainder() -> None:
    path = route()
    assert is_remainder(path, rest_from(path, 120, robot_offset=0.06), TOLERANCE)
    assert is_remainder(path, path.copy(), TOLERANCE)
    jitter = np.random.default_rng(1).uniform(-0.02, 0.02, (len(path) - 50, 2))
    shifted = rest_from(path, 50)
    shifted[:-1, :2] += jitter[:-1]  # another search's staircase, within a cell of 3 cm
    assert is_remainder(path, shifted, TOLERANCE)


def test_another_goal_is_not_the_remainder() -> None:
    path = route()
    moved, turned = rest_from(path, 120), rest_from(path, 120)
    moved[-1, 0] += 0.01
    turned[-1, 2] += 0.01
    assert not is_remainder(path, moved, TOLERANCE)
    assert not is_remainder(path, turned, TOLERANCE)


def test_a_detour_or_a_shortcut_is_not_the_remainder() -> None:
    path = route()
    detour = rest_from(path, 50)
    detour[50:80, 1] += 0.5  # around a new obstacle, 0.5 m aside
    assert not is_remainder(path, detour, TOLERANCE)
    corner = rest_from(path, 150)
    cut = np.vstack((corner[:20], corner[-20:]))  # skips the corner: the old path has poses far from it
    cut[:20, 2] = math.atan2(corner[-20, 1] - corner[19, 1], corner[-20, 0] - corner[19, 0])
    assert not is_remainder(path, cut, TOLERANCE)
    assert not is_remainder(path, rest_from(path, 120), 0.0)  # 0: never


def test_the_path_behind_the_robot_is_not_compared() -> None:
    """The old path's start, which the robot has passed, is not expected in the new plan."""
    path = route()
    assert is_remainder(path, rest_from(path, 250), TOLERANCE)


def _following(path: np.ndarray, ids: tuple[str, str, str] = IDS) -> PathFollowing:
    return PathFollowing(ids, path)


def test_the_remainder_keeps_every_plugin_state_and_swaps_the_path() -> None:
    path = route()
    old = _following(path)
    old.last_valid, old.turning_at_goal = 4.2, True
    checker = SimpleGoalChecker()
    checker.xy_reached = True
    controller, progress = Counting(), Counting()
    new = _following(rest_from(path, 300, robot_offset=0.03))
    assert new.take_over(old, Plugins(controller, checker, progress), TOLERANCE) is Takeover.REMAINDER
    assert (controller.resets, progress.resets, checker.xy_reached) == (0, 0, True)
    assert (new.last_valid, new.turning_at_goal) == (4.2, True)
    np.testing.assert_array_equal(new.handler.plan, rest_from(path, 300, robot_offset=0.03))


def test_another_path_with_the_same_controller_restarts_only_the_goal_checker() -> None:
    path = route()
    old = _following(path)
    old.last_valid, old.turning_at_goal = 4.2, True
    checker = SimpleGoalChecker()
    checker.xy_reached = True
    controller, progress = Counting(), Counting()
    elsewhere = path[:150].copy()  # another goal: the end of the first leg
    new = _following(elsewhere)
    assert new.take_over(old, Plugins(controller, checker, progress), TOLERANCE) is Takeover.NEW_PATH
    assert (controller.resets, progress.resets, checker.xy_reached) == (0, 0, False)
    assert (new.last_valid, new.turning_at_goal) == (4.2, False)


def test_another_progress_checker_restarts_while_the_controller_keeps_its_state() -> None:
    path = route()
    controller, progress = Counting(), Counting()
    new = _following(rest_from(path, 100), (IDS[0], IDS[1], "other_progress_checker"))
    assert new.take_over(_following(path), Plugins(controller, SimpleGoalChecker(), progress),
                         TOLERANCE) is Takeover.REMAINDER
    assert (controller.resets, progress.resets) == (0, 1)


def test_another_controller_or_no_running_goal_resets_every_plugin() -> None:
    path = route()
    for previous in (None, _following(path, ("OtherController", IDS[1], IDS[2]))):
        controller, checker, progress = Counting(), Counting(), Counting()
        new = _following(rest_from(path, 100))
        assert new.take_over(previous, Plugins(controller, checker, progress), TOLERANCE) is Takeover.FRESH
        assert (controller.resets, checker.resets, progress.resets) == (1, 1, 1)
        assert new.last_valid == -math.inf
