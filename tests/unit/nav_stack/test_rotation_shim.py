"""Rotation shim in front of DWB: in-place turns toward the path and onto the goal yaw, hand-over,
collision refusal, and a closed kinematic loop against DWB alone."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.control import (
    CostGrid,
    DWBController,
    NoValidControl,
    PathHandler,
    PolygonFootprint,
    SimpleGoalChecker,
    Twist2D,
)
from nav_stack.core.control.rotation_shim import RotationShim, RotationShimParams, sampled_heading_error
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from tests.unit.nav_stack.test_control import DT, polyline_path, unicycle, with_obstacle

SPEC = GridSpec(100, 100, 0.05, -2.5, -2.5)
FREE = CostGrid(np.zeros(SPEC.shape, np.uint8), SPEC)
ORIGIN = Pose2D(0.0, 0.0, 0.0)


def shim(**overrides: float | bool) -> RotationShim:
    return RotationShim(DWBController(), RotationShimParams(**overrides))  # type: ignore[arg-type]


def test_the_heading_is_taken_from_the_path_point_at_the_sampling_distance() -> None:
    path = polyline_path([(0.0, 0.0), (0.3, 0.0), (0.3, 1.0)])
    assert sampled_heading_error(ORIGIN, path, 0.2) == pytest.approx(0.0)
    assert sampled_heading_error(ORIGIN, path, 0.5) == pytest.approx(math.atan2(0.4, 0.3), abs=0.05)


def test_a_path_behind_the_robot_starts_with_an_in_place_turn_within_the_acceleration_limit() -> None:
    path = polyline_path([(0.0, 0.0), (-1.5, 0.0)])
    cmd = shim().compute_velocity(ORIGIN, Twist2D(0.0, 0.0), path, FREE)
    assert cmd.vx == 0.0 and abs(cmd.wz) == pytest.approx(3.2 * DT)


def test_below_the_threshold_the_primary_controller_drives() -> None:
    path = polyline_path([(0.0, 0.0), (1.5, 0.1)])
    expected = DWBController().compute_velocity(ORIGIN, Twist2D(0.2, 0.0), path, FREE)
    assert shim().compute_velocity(ORIGIN, Twist2D(0.2, 0.0), path, FREE) == expected


def test_once_turning_it_keeps_turning_down_to_the_disengage_threshold() -> None:
    rotation = shim(angular_disengage_threshold=0.3)
    path = polyline_path([(0.0, 0.0), (0.0, 1.5)])  # 90° to the left
    assert rotation.compute_velocity(ORIGIN, Twist2D(0.0, 0.0), path, FREE).vx == 0.0
    half_way = Pose2D(0.0, 0.0, math.pi / 2 - 0.5)  # 0.5 rad left: under 0.785, over 0.3
    cmd = rotation.compute_velocity(half_way, Twist2D(0.0, 1.0), path, FREE)
    assert cmd.vx == 0.0 and cmd.wz > 0.0
    aligned = Pose2D(0.0, 0.0, math.pi / 2 - 0.2)
    rotation.compute_velocity(aligned, Twist2D(0.0, 0.0), path, FREE)
    assert not rotation.rotating  # DWB has the path


def test_near_the_goal_it_turns_onto_the_goal_yaw_and_stays_on_it_when_jitter_moves_the_robot() -> None:
    rotation = shim(rotate_to_goal_heading=True)
    path = polyline_path([(0.0, 0.0), (0.2, 0.0)])
    path[-1, 2] = math.pi / 2
    assert rotation.compute_velocity(ORIGIN, Twist2D(0.0, 0.0), path, FREE).wz > 0.0
    drifted = Pose2D(-0.1, 0.0, 0.5)  # now 0.3 m from the goal
    cmd = rotation.compute_velocity(drifted, Twist2D(0.0, 1.0), path, FREE)
    assert cmd.vx == 0.0 and cmd.wz > 0.0
    nearly = Pose2D(-0.1, 0.0, math.pi / 2 - 0.01)  # brakes to stop on the yaw
    braking = rotation.compute_velocity(nearly, Twist2D(0.0, 1.8), path, FREE)
    assert braking.wz == pytest.approx(1.8 - 3.2 * DT)


def test_a_turn_that_swings_the_footprint_into_a_wall_is_refused() -> None:
    long_robot = PolygonFootprint(((0.5, 0.1), (0.5, -0.1), (-0.1, -0.1), (-0.1, 0.1)))
    grid = with_obstacle(SPEC, -0.5, 0.5, 0.3, 0.4, radius=0.0)  # a wall just left of the nose
    rotation = RotationShim(DWBController(), RotationShimParams(), long_robot)
    left = polyline_path([(0.0, 0.0), (-0.3, 1.5)])
    turning = Twist2D(0.0, 1.8)  # the next second of this turn is what gets checked, as in Nav2
    with pytest.raises(NoValidControl):
        rotation.compute_velocity(ORIGIN, turning, left, grid)
    assert rotation.compute_velocity(ORIGIN, turning, left, FREE).wz > 0.0


def steps_to_goal(controller: DWBController | RotationShim, path: np.ndarray, goal_yaw: float) -> int:
    """Control cycles of a closed kinematic loop until the goal checker accepts (0.25 m, 0.25 rad)."""
    path = path.copy()
    path[-1, 2] = goal_yaw
    handler, checker = PathHandler(), SimpleGoalChecker()
    handler.set_plan(path)
    pose, vel = ORIGIN, Twist2D(0.0, 0.0)
    for step in range(2000):
        if checker.is_goal_reached(pose, handler.goal, vel):
            return step
        vel = controller.compute_velocity(pose, vel, handler.local_path(pose, ORIGIN, FREE), FREE)
        pose = unicycle(pose, vel)
    raise AssertionError(f"not reached, stopped at {pose}")


def test_with_the_shim_dwb_reaches_a_goal_behind_it_sooner() -> None:
    path = polyline_path([(0.0, 0.0), (-1.5, 0.0)])
    alone = steps_to_goal(DWBController(), path, math.pi / 2)
    shimmed = steps_to_goal(shim(rotate_to_goal_heading=True), path, math.pi / 2)
    print(f"cycles to the goal: DWB {alone}, shim + DWB {shimmed}")
    assert shimmed < 0.85 * alone
