"""MPPIController on small synthetic local costmaps: it follows paths, turns toward a path behind it,
keeps off walls, respects each motion model's limits, repeats with its seed, and falls back as Nav2's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.control import NoValidControl, Twist2D
from nav_stack.core.control.mppi import (
    AckermannConstraints,
    MPPIController,
    MPPIParams,
    PathFollowCriticParams,
    trajectory_markers,
)
from nav_stack.core.control.mppi.local_path import first_inversion, prune
from nav_stack.core.geometry import Pose2D, angle_diff
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE
from tests.helpers.mppi_scenes import (
    INFLATION,
    costmap,
    in_window,
    nearest_on,
    polyline,
    step,
    straight_path,
    window,
)

DT = 0.05


def drive(controller: MPPIController, path: np.ndarray, robot: Pose2D, cycles: int,
          boxes: tuple[tuple[float, float, float, float], ...] = ()) -> tuple[list[Pose2D], list[Twist2D]]:
    """Closed loop on a kinematic robot that does what it is told; the rolling window follows it."""
    velocity, poses, commands = Twist2D(0.0, 0.0), [robot], []
    for _ in range(cycles):
        grid = costmap(window(robot.x, robot.y), boxes)
        command = controller.compute_velocity(robot, velocity, in_window(nearest_on(path, robot), grid), grid)
        robot = step(robot, command, DT, controller.last_command[1])
        velocity = command
        poses.append(robot)
        commands.append(command)
    return poses, commands


def test_it_follows_a_straight_path_at_up_to_vx_max() -> None:
    poses, commands = drive(MPPIController(inflation=INFLATION), straight_path((0.0, 0.0), 0.0, 5.0),
                            Pose2D(0.0, 0.0, 0.0), 60)
    assert poses[-1].x > 1.0
    assert max(abs(p.y) for p in poses) < 0.05
    assert max(c.vx for c in commands) == pytest.approx(0.5, abs=0.02)


def test_it_turns_toward_a_path_behind_it() -> None:
    poses, _ = drive(MPPIController(inflation=INFLATION), straight_path((0.0, 0.0), 0.0, 5.0),
                     Pose2D(0.0, 0.0, math.pi), 100)
    assert abs(angle_diff(poses[-1].yaw, 0.0)) < 0.5
    assert poses[-1].x > poses[0].x + 0.3


def test_it_never_drives_into_a_wall_across_the_path() -> None:
    wall = ((0.9, -2.0, 1.1, 2.0),)
    poses, commands = drive(MPPIController(inflation=INFLATION), straight_path((0.0, 0.0), 0.0, 5.0),
                            Pose2D(0.0, 0.0, 0.0), 100, wall)
    grid = costmap(window(0.5, 0.0, size=4.0), wall)
    centre_costs = grid.cost_at(np.array([p.x for p in poses]), np.array([p.y for p in poses]))
    assert centre_costs.max() < INSCRIBED_INFLATED_OBSTACLE
    assert abs(commands[-1].vx) < 0.05  # it waits in front of the wall


@pytest.mark.parametrize("model", ["DiffDrive", "Omni", "Ackermann"])
def test_commands_keep_the_velocity_and_acceleration_limits(model: str) -> None:
    p = MPPIParams(motion_model=model, batch_size=500, vx_max=0.4, vx_min=-0.2, wz_max=1.0, vy_max=0.3)
    controller = MPPIController(p, ackermann=AckermannConstraints(0.5), inflation=INFLATION)
    path = polyline([(0.0, 0.0), (0.6, 0.0), (0.8, 0.8), (0.0, 1.2)])
    rng = np.random.default_rng(5)
    robot = Pose2D(0.0, 0.0, 0.0)
    for _ in range(40):
        vx = float(rng.uniform(p.vx_min, p.vx_max))
        wz_limit = min(p.wz_max, abs(vx) / 0.5) if model == "Ackermann" else p.wz_max  # a feasible state
        velocity = Twist2D(vx, float(rng.uniform(-wz_limit, wz_limit)))
        grid = costmap(window(robot.x, robot.y))
        cmd = controller.compute_velocity(robot, velocity, in_window(nearest_on(path, robot), grid), grid)
        vy = controller.last_command[1]
        assert p.vx_min - 1e-12 <= cmd.vx <= p.vx_max + 1e-12
        assert abs(cmd.wz) <= p.wz_max + 1e-12
        assert abs(cmd.vx - velocity.vx) <= p.ax_max * DT + 1e-9
        if model != "Ackermann":  # its turning radius limit comes last and may brake wz harder (as Nav2)
            assert abs(cmd.wz - velocity.wz) <= p.az_max * DT + 1e-9
        assert abs(vy) <= (min(p.vy_max, p.ay_max * DT) + 1e-12 if model == "Omni" else 0.0)
        if model == "Ackermann":
            assert abs(cmd.wz) * 0.5 <= abs(cmd.vx) + 1e-12  # turning radius >= min_turning_r
        robot = step(robot, cmd, DT, vy)


def test_ackermann_turns_no_tighter_than_min_turning_r() -> None:
    p = MPPIParams(motion_model="Ackermann", vx_min=0.0)
    controller = MPPIController(p, ackermann=AckermannConstraints(0.8), inflation=INFLATION)
    path = polyline([(0.0, 0.0), (0.3, 0.0), (0.3, 1.0)])  # a right-angle bend
    _, commands = drive(controller, path, Pose2D(0.0, 0.0, 0.0), 60)
    turning = [c for c in commands if abs(c.wz) > 1e-6]
    assert turning, "it never turned"
    assert min(abs(c.vx / c.wz) for c in turning) >= 0.8 - 1e-9


def test_the_same_seed_gives_the_same_commands_and_another_seed_others() -> None:
    path = straight_path((0.0, 0.0), 0.3, 3.0)
    runs = [drive(MPPIController(MPPIParams(random_seed=seed), inflation=INFLATION), path,
                  Pose2D(0.0, 0.0, 0.0), 5)[1] for seed in (7, 7, 8)]
    assert runs[0] == runs[1]
    assert runs[0] != runs[2]


def test_all_trajectories_colliding_resets_retries_and_raises_no_valid_control() -> None:
    grid = costmap(window(), [(-1.5, -1.5, 1.5, 1.5)])
    controller = MPPIController(MPPIParams(batch_size=100, retry_attempt_limit=2), inflation=INFLATION)
    calls = []
    iterate = controller.optimizer.kernels.iterate
    controller.optimizer.kernels.iterate = lambda *a: calls.append(1) or iterate(*a)  # type: ignore[method-assign,func-returns-value]
    with pytest.raises(NoValidControl, match="collides"):
        controller.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), straight_path((0, 0), 0, 1),
                                    grid)
    assert len(calls) == 3  # the first try and retry_attempt_limit retries, each after a reset
    assert not controller.optimizer.sequence.any()


def test_the_reference_kernels_drive_as_well() -> None:
    controller = MPPIController(MPPIParams(batch_size=400), inflation=INFLATION, kernels="reference")
    poses, _ = drive(controller, straight_path((0.0, 0.0), 0.0, 5.0), Pose2D(0.0, 0.0, 0.0), 30)
    assert poses[-1].x > 0.4 and abs(poses[-1].y) < 0.05


def test_critic_parameters_change_the_behaviour() -> None:
    """A PathFollowCritic weighted 0 no longer pulls the robot along: it barely moves."""
    controller = MPPIController(MPPIParams(critics=("PathFollowCritic",)),
                                {"PathFollowCritic": PathFollowCriticParams(cost_weight=0.0)},
                                inflation=INFLATION)
    poses, _ = drive(controller, straight_path((0.0, 0.0), 0.0, 5.0), Pose2D(0.0, 0.0, 0.0), 30)
    pulled, _ = drive(MPPIController(MPPIParams(critics=("PathFollowCritic",)), inflation=INFLATION),
                      straight_path((0.0, 0.0), 0.0, 5.0), Pose2D(0.0, 0.0, 0.0), 30)
    assert pulled[-1].x > poses[-1].x + 0.3


@pytest.mark.parametrize("changes, message", [
    ({"motion_model": "Tank"}, "motion_model"),
    ({"critics": ("CostCritic", "NoSuchCritic")}, "NoSuchCritic"),
    ({"controller_frequency": 10.0}, "model_dt"),
    ({"temperature": 0.0}, "temperature"),
    ({"vx_min": 1.0}, "vx_min"),
])
def test_bad_parameters_are_refused_with_their_name(changes: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        MPPIParams(**changes)  # type: ignore[arg-type]


def test_the_critics_see_prune_distance_of_the_path_and_stop_at_a_cusp() -> None:
    path = polyline([(0.0, 0.0), (1.0, 0.0), (0.4, 0.0)])
    assert first_inversion(path) == 21  # poses 0..20: up to the cusp at (1, 0)
    assert np.allclose(path[first_inversion(path) - 1, :2], (1.0, 0.0))
    assert len(prune(path, 0.5)) == 11
    p = MPPIParams(enforce_path_inversion=True, batch_size=200)
    controller = MPPIController(p, inflation=INFLATION)
    grid = costmap(window())
    controller.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, grid)
    assert np.allclose(controller.transformed_plan[-1, :2], (1.0, 0.0))
    at_cusp = Pose2D(0.95, 0.0, path[20, 2])
    controller.compute_velocity(at_cusp, Twist2D(0.0, 0.0), nearest_on(path, at_cusp), grid)
    assert controller.transformed_plan[-1, 0] < 0.5  # past the cusp, the rest of the path


def test_the_visualisation_thins_the_samples_as_jazzy_does() -> None:
    controller = MPPIController(MPPIParams(batch_size=100, time_steps=30), inflation=INFLATION)
    grid = costmap(window())
    controller.compute_velocity(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), straight_path((0, 0), 0, 1), grid)
    x, y = controller.sampled_trajectories
    candidates, optimal = trajectory_markers(x, y, controller.last_trajectory, 5, 3)
    assert len(candidates.ids) == 20 * 10 and len(optimal.ids) == 30
    assert list(optimal.ids[:2]) == [200, 201]
    assert np.allclose(candidates.centres[1, :2], (x[0, 3], y[0, 3]))
    assert np.allclose(candidates.colours[1], (0.0, 3 / 30, 1 - 3 / 30, 1.0))
    assert np.allclose(optimal.sizes[-1], (0.07, 0.07, 0.09))
    assert controller.last_trajectory.shape == (30, 3)
