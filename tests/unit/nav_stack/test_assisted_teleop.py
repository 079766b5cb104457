"""AssistedTeleop (nav2_behaviors, Jazzy) without ROS: the projection, the speed scaling, the goal's end."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.behaviors import (
    AssistedTeleop,
    AssistedTeleopErrorCode,
    AssistedTeleopParams,
    TeleopCommand,
    teleop_scale,
)
from nav_stack.core.behaviors.assisted_teleop import projected_poses, projection_times
from nav_stack.core.control.base import CostGrid, PolygonFootprint
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec

SQUARE = PolygonFootprint(((0.1, 0.1), (0.1, -0.1), (-0.1, -0.1), (-0.1, 0.1)))
PARAMS = AssistedTeleopParams()


def wall_grid() -> CostGrid:
    """4 m x 2 m of free space with a lethal wall across x = 1.00 .. 1.05 m."""
    spec = GridSpec(80, 40, 0.05, -0.5, -1.0)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    costs[:, 30] = LETHAL_OBSTACLE
    return CostGrid(costs, spec)


def test_the_projection_steps_like_nav2s_loop() -> None:
    times = projection_times(PARAMS)
    assert len(times) == 10 and times[-1] < 1.0  # ten float steps of 0.1 stay below 1.0
    assert projection_times(AssistedTeleopParams(projection_time=0.5, simulation_time_step=0.2)) == \
        pytest.approx([0.2, 0.4])


def test_projected_poses_turn_after_each_step() -> None:
    straight = projected_poses(Pose2D(1.0, 2.0, math.pi / 2), TeleopCommand(0.5, 0.0, 0.0), 0.1, 4)
    expected = [[1.0, 2.05], [1.0, 2.1], [1.0, 2.15], [1.0, 2.2]]
    np.testing.assert_allclose(straight[:, :2], expected, atol=1e-12)
    turning = projected_poses(Pose2D(0.0, 0.0, 0.0), TeleopCommand(1.0, 0.0, 1.0), 0.1, 2)
    # the first step moves along the start heading, the second along the heading after one step
    np.testing.assert_allclose(turning[0], [0.1, 0.0, 0.1], atol=1e-12)
    np.testing.assert_allclose(turning[1], [0.1 + 0.1 * math.cos(0.1), 0.1 * math.sin(0.1), 0.2], atol=1e-12)
    sideways = projected_poses(Pose2D(0.0, 0.0, math.pi / 2), TeleopCommand(0.0, 1.0, 0.0), 0.1, 1)
    np.testing.assert_allclose(sideways[0, :2], [-0.1, 0.0], atol=1e-12)  # +y of the robot is -x here


def test_a_command_toward_a_wall_is_slowed_by_the_time_to_contact() -> None:
    grid = wall_grid()
    assert teleop_scale(Pose2D(0.0, 0.0, 0.0), TeleopCommand(0.5, 0.0, 0.0), grid, SQUARE, PARAMS) == 1.0
    # at 1.2 m/s the square's nose (x + 0.1) enters the wall after the 8th step: 0.7 s still free
    scale = teleop_scale(Pose2D(0.0, 0.0, 0.0), TeleopCommand(1.2, 0.0, 0.5), grid, SQUARE, PARAMS)
    assert scale == pytest.approx(0.8)
    assert teleop_scale(Pose2D(0.0, 0.0, 0.0), TeleopCommand(1.2, 0.0, 0.0), grid, SQUARE,
                        AssistedTeleopParams(projection_time=2.0)) == pytest.approx(0.4)


def test_a_command_that_collides_at_the_first_step_is_stopped_and_backing_away_is_not() -> None:
    grid = wall_grid()
    close = Pose2D(0.88, 0.0, 0.0)  # nose at 0.98 m, 2 cm from the wall
    assert teleop_scale(close, TeleopCommand(0.5, 0.0, 0.0), grid, SQUARE, PARAMS) == 0.0
    assert teleop_scale(close, TeleopCommand(-0.5, 0.0, 0.0), grid, SQUARE, PARAMS) == 1.0
    assert teleop_scale(close, TeleopCommand(0.0, 0.5, 0.0), grid, SQUARE, PARAMS) == 1.0  # along the wall


def test_without_a_costmap_every_command_is_stopped() -> None:
    assert teleop_scale(Pose2D(0.0, 0.0, 0.0), TeleopCommand(0.2, 0.0, 0.0), None, SQUARE, PARAMS) == 0.0


def test_the_behavior_forwards_the_scaled_command_until_preempted() -> None:
    teleop = AssistedTeleop()
    teleop.teleop(TeleopCommand(1.2, 0.0, 0.5))  # heard before the goal: kept, as Nav2 keeps it
    teleop.start(0.0, now=10.0, footprint=SQUARE)
    assert teleop.check(25.0) is None  # time_allowance 0: no limit
    assert teleop.current_teleop_duration == 15.0
    cmd = teleop.command(Pose2D(0.0, 0.0, 0.0), wall_grid())
    assert cmd == pytest.approx(TeleopCommand(1.2 * 0.8, 0.0, 0.5 * 0.8))
    teleop.preempt()
    end = teleop.check(26.0)
    assert end is not None and end.succeeded and end.total_elapsed_time == 16.0
    teleop.finish()
    assert teleop.teleop_command == TeleopCommand(0.0, 0.0, 0.0)
    teleop.start(5.0, now=30.0, footprint=SQUARE)
    assert teleop.check(31.0) is None  # the preempt of the last goal does not end this one


def test_the_time_allowance_ends_the_goal_with_timeout() -> None:
    teleop = AssistedTeleop()
    teleop.start(2.0, now=0.0)
    assert teleop.check(2.0) is None
    end = teleop.check(2.1)
    assert end is not None and end.error_code == AssistedTeleopErrorCode.TIMEOUT == 731
    assert "2.00 s" in end.error_msg


@pytest.mark.parametrize("bad", [{"projection_time": 0.0}, {"simulation_time_step": -0.1}])
def test_bad_parameters_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError):
        AssistedTeleopParams(**bad)
