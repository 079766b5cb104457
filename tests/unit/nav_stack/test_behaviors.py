"""Spin, BackUp, DriveOnHeading and Wait command laws, error codes and collision look-ahead."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.behaviors import (
    BackUp,
    BackUpErrorCode,
    BehaviorParams,
    BehaviorResult,
    DriveGoal,
    DriveOnHeading,
    DriveOnHeadingErrorCode,
    Spin,
    SpinErrorCode,
    SpinGoal,
    Wait,
    spin_speed,
)
from nav_stack.core.control import CostGrid, Twist2D
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec

PERIOD = 0.1  # behavior_server cycle_frequency 10 Hz
SPEC = GridSpec(80, 80, 0.05, -2.0, -2.0)


def free_grid() -> CostGrid:
    return CostGrid(np.zeros(SPEC.shape, np.uint8), SPEC)


def grid_with_wall_at_x(x: float) -> CostGrid:
    costs = np.zeros(SPEC.shape, np.uint8)
    mx, _ = SPEC.world_to_cell(x, 0.0)
    costs[:, int(mx)] = LETHAL_OBSTACLE
    return CostGrid(costs, SPEC)


def run(
    behavior: Spin | DriveOnHeading, pose: Pose2D, grid: CostGrid, steps: int = 500
) -> tuple[BehaviorResult, list[Twist2D], Pose2D]:
    commands: list[Twist2D] = []
    for k in range(steps):
        out = behavior.step(pose, k * PERIOD, grid)
        if isinstance(out, BehaviorResult):
            return out, commands, pose
        commands.append(out)
        yaw = pose.yaw + out.wz * PERIOD
        pose = Pose2D(
            pose.x + out.vx * math.cos(pose.yaw) * PERIOD,
            pose.y + out.vx * math.sin(pose.yaw) * PERIOD,
            math.remainder(yaw, 2 * math.pi),
        )
    raise AssertionError("behavior never finished")


def test_spin_speed_law() -> None:
    p = BehaviorParams()
    assert spin_speed(p, 1.0, 1.0) == 1.0  # sqrt(6.4) clamps at max 1.0
    assert spin_speed(p, 0.1, -1.0) == pytest.approx(-math.sqrt(2 * 3.2 * 0.1))  # 0.8 rad/s, sign of target
    assert spin_speed(p, 0.01, 1.0) == 0.4  # floor at min_rotational_vel


def test_spin_turns_the_target_angle_beyond_pi_and_decelerates() -> None:
    spin = Spin()
    assert spin.start(SpinGoal(-4.0, time_allowance=20.0), Pose2D(0.0, 0.0, 3.0), 0.0) is None
    result, commands, _pose = run(spin, Pose2D(0.0, 0.0, 3.0), free_grid())
    assert result.succeeded and result.error_code == SpinErrorCode.NONE
    assert all(c.wz < 0 and c.vx == 0.0 for c in commands)
    assert spin.angular_distance_traveled == pytest.approx(4.0, abs=0.1)
    assert abs(commands[-1].wz) < abs(commands[len(commands) // 2].wz) or abs(commands[-1].wz) == 0.4


def test_spin_times_out() -> None:
    spin = Spin()
    spin.start(SpinGoal(3.0, time_allowance=1.0), Pose2D(0.0, 0.0, 0.0), 0.0)
    result, _, _ = run(spin, Pose2D(0.0, 0.0, 0.0), free_grid())
    assert result.error_code == SpinErrorCode.TIMEOUT == 701


def test_spin_with_a_polygon_footprint_near_a_wall_reports_collision_ahead() -> None:
    from nav_stack.core.control import PolygonFootprint

    long_robot = PolygonFootprint(((0.6, 0.1), (0.6, -0.1), (-0.1, -0.1), (-0.1, 0.1)))
    spin = Spin(footprint=long_robot)
    pose = Pose2D(0.0, 0.0, -math.pi / 2)  # nose points at -y; a wall at x = 0.4 blocks a left turn
    spin.start(SpinGoal(1.57), pose, 0.0)
    result, commands, _ = run(spin, pose, grid_with_wall_at_x(0.4))
    assert result.error_code == SpinErrorCode.COLLISION_AHEAD == 703 and commands == []


def test_backup_normalises_signs_and_stops_at_distance() -> None:
    backup = BackUp()
    assert backup.start(DriveGoal(0.3, 0.05), Pose2D(0.0, 0.0, 0.0), 0.0) is None  # positive as clients send
    result, commands, pose = run(backup, Pose2D(0.0, 0.0, 0.0), free_grid())
    assert result.succeeded
    assert all(c.vx == -0.05 and c.wz == 0.0 for c in commands)
    assert -0.36 < pose.x <= -0.3 and backup.distance_traveled >= 0.3


def test_drive_on_heading_input_rules() -> None:
    drive = DriveOnHeading()
    mismatch = drive.start(DriveGoal(0.5, -0.1), Pose2D(0.0, 0.0, 0.0), 0.0)
    assert mismatch is not None and mismatch.error_code == DriveOnHeadingErrorCode.INVALID_INPUT == 724
    sideways = drive.start(DriveGoal(0.5, 0.1, target_y=0.2), Pose2D(0.0, 0.0, 0.0), 0.0)
    assert sideways is not None and sideways.error_code == 724
    backup_sideways = BackUp().start(DriveGoal(0.5, 0.1, target_z=0.1), Pose2D(0.0, 0.0, 0.0), 0.0)
    assert backup_sideways is not None and backup_sideways.error_code == BackUpErrorCode.INVALID_INPUT == 713
    assert drive.start(DriveGoal(-0.2, -0.1), Pose2D(0.0, 0.0, 0.0), 0.0) is None  # both negative: reverse
    result, commands, pose = run(drive, Pose2D(0.0, 0.0, 0.0), free_grid())
    assert result.succeeded and commands[0].vx == -0.1 and pose.x <= -0.2


def test_drive_on_heading_collision_lookahead_and_timeout() -> None:
    drive = DriveOnHeading()
    drive.start(DriveGoal(1.0, 0.2), Pose2D(0.0, 0.0, 0.0), 0.0)
    result, _commands, pose = run(drive, Pose2D(0.0, 0.0, 0.0), grid_with_wall_at_x(0.8))
    assert result.error_code == DriveOnHeadingErrorCode.COLLISION_AHEAD == 723
    assert pose.x < 0.8 - 0.3  # stopped well before the wall: 2 s × 0.2 m/s look-ahead
    short = DriveOnHeading()
    short.start(DriveGoal(0.3, 0.2), Pose2D(0.0, 0.0, 0.0), 0.0)  # ends 0.5 m before the wall: no alarm
    assert run(short, Pose2D(0.0, 0.0, 0.0), grid_with_wall_at_x(0.8))[0].succeeded
    slow = BackUp()
    slow.start(DriveGoal(1.0, 0.05, time_allowance=2.0), Pose2D(0.0, 0.0, 0.0), 0.0)
    assert run(slow, Pose2D(0.0, 0.0, 0.0), free_grid())[0].error_code == BackUpErrorCode.TIMEOUT == 711


def test_wait() -> None:
    wait = Wait()
    assert wait.start(1.0, 5.0) is None
    assert wait.step(5.5) is None and wait.time_left == pytest.approx(0.5)
    done = wait.step(6.0)
    assert done is not None and done.succeeded and done.total_elapsed_time == pytest.approx(1.0)
    refused = Wait().start(-1.0, 0.0)
    assert refused is not None and not refused.succeeded
