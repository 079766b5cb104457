"""PathFollowing: the controller server's cycle as pure decisions (nav_stack/core/control/follow_path.py).

The real goal and progress checkers; a scripted controller that returns a command or raises
NoValidControl, so each rule of the cycle is seen on its own: hold without a costmap and fail after
costmap_update_timeout, succeed at the goal, fail without progress (saying why), tolerate a controller
without a command for failure_tolerance s (0: at once with its own code; -1: for ever).
"""

from __future__ import annotations

import numpy as np

from nav_stack.core.control import (
    ControllerErrorCode,
    CostGrid,
    NoValidControl,
    SimpleGoalChecker,
    SimpleProgressChecker,
    Twist2D,
)
from nav_stack.core.control.follow_path import Action, CycleInputs, PathFollowing, Plugins
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec

SPEC = GridSpec(60, 60, 0.05, -1.5, -1.5)
GRID = CostGrid(np.zeros(SPEC.shape, np.uint8), SPEC)
PATH = np.array([[0.1 * i, 0.0, 0.0] for i in range(11)])  # 1 m along x
IDS = ("FollowPath", "general_goal_checker", "progress_checker")


class ScriptedController:
    """Returns ``command``, or raises NoValidControl while ``valid`` is False."""

    def __init__(self) -> None:
        self.valid = True
        self.command = Twist2D(0.2, 0.0)
        self.calls = 0

    def reset(self) -> None:
        pass

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: np.ndarray, grid: CostGrid) -> Twist2D:
        self.calls += 1
        if not self.valid:
            raise NoValidControl("all trajectories collide")
        return self.command


def _rig() -> tuple[PathFollowing, Plugins, ScriptedController]:
    controller = ScriptedController()
    plugins = Plugins(controller, SimpleGoalChecker(), SimpleProgressChecker())
    return PathFollowing(IDS, PATH), plugins, controller


def _cycle(now: float, x: float, yaw: float = 0.0) -> CycleInputs:
    robot = Pose2D(x, 0.0, yaw)
    return CycleInputs(now, robot, robot, Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), GRID)


def test_without_a_costmap_the_robot_holds_then_the_goal_fails_after_the_timeout() -> None:
    following, _, _ = _rig()
    assert following.without_costmap(0.0, True, 0.3).action is Action.HOLD
    assert following.without_costmap(0.3, True, 0.3).action is Action.HOLD
    failed = following.without_costmap(0.35, True, 0.3)
    assert (failed.action, failed.code) == (Action.ABORT, ControllerErrorCode.UNKNOWN)
    assert "no data" in failed.message
    cleared = PathFollowing(IDS, PATH)
    cleared.without_costmap(0.0, False, 0.3)
    assert "no scan since it was cleared" in cleared.without_costmap(0.5, False, 0.3).message


def test_the_controller_drives_and_the_goal_succeeds_where_the_checker_says() -> None:
    following, plugins, controller = _rig()
    drive = following.step(_cycle(0.0, 0.0), plugins, 0.3)
    assert (drive.action, drive.cmd) == (Action.DRIVE, Twist2D(0.2, 0.0))
    assert abs(drive.distance_to_goal - 1.0) < 1e-6
    done = following.step(_cycle(0.1, 0.95), plugins, 0.3)  # within xy_goal_tolerance (0.25 m) and heading
    assert done.action is Action.SUCCEED and controller.calls == 1


def test_no_progress_fails_the_goal_and_says_how_little_the_robot_moved() -> None:
    following, plugins, _ = _rig()
    allowance = plugins.progress_checker.params.movement_time_allowance  # 10 s
    assert following.step(_cycle(0.0, 0.0), plugins, 0.3).action is Action.DRIVE
    assert following.step(_cycle(allowance, 0.1), plugins, 0.3).action is Action.DRIVE
    failed = following.step(_cycle(allowance + 0.05, 0.1), plugins, 0.3, lambda: " (battery empty)")
    assert (failed.action, failed.code) == (Action.ABORT, ControllerErrorCode.FAILED_TO_MAKE_PROGRESS)
    assert failed.message == f"the robot moved less than 0.5 m in {allowance} s (battery empty)"


def test_the_final_rotation_gets_a_fresh_progress_window_in_which_turning_counts() -> None:
    following, plugins, _ = _rig()
    allowance = plugins.progress_checker.params.movement_time_allowance
    assert following.step(_cycle(0.0, 0.5), plugins, 0.3).action is Action.DRIVE
    # the goal's xy is reached 9 s later, facing away: the old window would fail a second later
    turning = _cycle(9.0, 0.95, yaw=2.0)
    assert following.step(turning, plugins, 0.3).action is Action.DRIVE and following.turning_at_goal
    assert following.step(_cycle(9.0 + allowance, 0.95, yaw=2.0), plugins, 0.3).action is Action.DRIVE
    failed = following.step(_cycle(9.05 + allowance, 0.95, yaw=2.0), plugins, 0.3)
    assert failed.action is Action.ABORT and "turned less than" in failed.message


def test_no_valid_command_stops_the_robot_until_failure_tolerance_then_patience_is_exceeded() -> None:
    following, plugins, controller = _rig()
    assert following.step(_cycle(0.0, 0.0), plugins, 0.3).action is Action.DRIVE
    controller.valid = False
    for now in (0.05, 0.2, 0.3):
        held = following.step(_cycle(now, 0.0), plugins, 0.3)
        assert (held.action, held.cmd) == (Action.DRIVE, Twist2D(0.0, 0.0))
    failed = following.step(_cycle(0.35, 0.0), plugins, 0.3)
    assert (failed.action, failed.code) == (Action.ABORT, ControllerErrorCode.PATIENCE_EXCEEDED)
    assert failed.message == "no valid command for 0.3 s: all trajectories collide"


def test_failure_tolerance_zero_fails_at_once_and_minus_one_never() -> None:
    following, plugins, controller = _rig()
    controller.valid = False
    at_once = following.step(_cycle(0.0, 0.0), plugins, 0.0)
    assert (at_once.action, at_once.code) == (Action.ABORT, ControllerErrorCode.NO_VALID_CONTROL)
    patient, plugins, controller = _rig()
    controller.valid = False
    assert all(patient.step(_cycle(t, 0.0), plugins, -1.0).action is Action.DRIVE for t in (0.0, 5.0, 9.9))


def test_a_preempting_goal_takes_over_the_timing_of_the_one_it_replaces() -> None:
    old, plugins, controller = _rig()
    old.step(_cycle(0.0, 0.0), plugins, 0.3)
    controller.valid = False
    old.step(_cycle(0.2, 0.0), plugins, 0.3)  # no valid command since 0.0
    new = PathFollowing(IDS, PATH)
    new.continue_from(old)
    assert new.step(_cycle(0.35, 0.0), plugins, 0.3).code == ControllerErrorCode.PATIENCE_EXCEEDED
