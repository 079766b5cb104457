"""The compiled MPPI iteration (kernels_jit) computes what the numpy reference does, given the same noise,
and so does a whole compiled controller cycle; the compiled noise is standard normal."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import pytest

from nav_stack.core.control import CircleFootprint, PolygonFootprint, Twist2D
from nav_stack.core.control.mppi import CRITIC_PARAMS, MPPIController, MPPIParams, sequence_jit
from nav_stack.core.control.mppi.kernels_jit import JitKernels
from nav_stack.core.control.mppi.noise import NoiseGenerator, standard_normal_fast
from nav_stack.core.control.mppi.reference import ReferenceKernels, poses
from nav_stack.core.control.mppi.scene import FootprintModel, Rollouts, Scene
from nav_stack.core.geometry import Pose2D
from tests.helpers.mppi_scenes import INFLATION, costmap, in_window, nearest_on, polyline, step, window

BATCH, STEPS = 300, 56
WAFFLE = PolygonFootprint(((-0.2, -0.15), (0.07, -0.15), (0.07, 0.15), (-0.2, 0.15)))


def _critics(**changes: dict[str, object]) -> list[tuple[str, object]]:
    """Every critic, with their defaults changed by ``changes[name]``."""
    return [(name, dataclasses.replace(cls(), **changes.get(name, {})))
            for name, cls in CRITIC_PARAMS.items()]


CASES: dict[str, dict[str, Any]] = {
    "diff drive, obstacles, path ahead": dict(robot=Pose2D(0.0, 0.05, 0.1), speed=Twist2D(0.2, 0.1)),
    "diff drive, near the goal": dict(robot=Pose2D(1.0, 0.0, 0.3), speed=Twist2D(0.1, 0.0)),
    "diff drive, facing away (path angle)": dict(robot=Pose2D(0.0, 0.0, 2.8), speed=Twist2D(0.0, 0.0)),
    "omni, footprint": dict(robot=Pose2D(0.0, 0.0, 0.0), speed=Twist2D(0.3, -0.2), model="Omni",
                            footprint=WAFFLE, consider=True),
    "ackermann, path orientations": dict(robot=Pose2D(0.2, -0.1, -0.3), speed=Twist2D(-0.1, 0.4),
                                         model="Ackermann", mode=2, orient=True),
    "no reversing, mode 1": dict(robot=Pose2D(0.0, 0.0, -2.0), speed=Twist2D(0.0, 0.0), vx_min=0.0, mode=1),
}


@pytest.mark.parametrize("case", list(CASES))
def test_the_compiled_iteration_gives_the_reference_costs_poses_and_sequence(case: str) -> None:
    c = CASES[case]
    params = MPPIParams(batch_size=BATCH, time_steps=STEPS, critics=tuple(CRITIC_PARAMS),
                        motion_model=str(c.get("model", "DiffDrive")), vx_min=float(c.get("vx_min", -0.35)))
    consider = bool(c.get("consider", False))
    critics = _critics(CostCritic={"consider_footprint": consider},
                       ObstaclesCritic={"consider_footprint": consider, "inflation_radius": INFLATION[0],
                                        "cost_scaling_factor": INFLATION[1]},
                       PathAngleCritic={"mode": c.get("mode", 0), "offset_from_furthest": 10},
                       PathAlignCritic={"use_path_orientations": c.get("orient", False),
                                        "offset_from_furthest": 2})
    grid = costmap(window(), [(0.5, 0.3, 0.8, 0.6), (0.9, -0.7, 1.1, -0.4), (-0.6, -0.2, -0.5, 0.2)])
    path = in_window(polyline([(0.0, 0.0), (0.8, 0.1), (1.2, -0.2), (1.4, 0.0)]), grid)
    footprint = FootprintModel.of(c.get("footprint", CircleFootprint(0.22)), 0.22, INFLATION)
    robot = c["robot"]
    scene = Scene.make(robot, c["speed"], path, path[-1], grid, footprint)
    rng = np.random.default_rng(hash(case) % 1000)
    noise = NoiseGenerator(rng, BATCH, STEPS, holonomic=True).noise
    sequence = rng.normal(0.0, 0.2, (3, STEPS))
    outputs = []
    for kernels in (ReferenceKernels, JitKernels):
        rollouts = Rollouts.empty(BATCH, STEPS)
        mean, costs, fail = kernels(params, critics, 0.3).iterate(sequence.copy(), noise, scene, rollouts)
        outputs.append((mean, costs.copy(), fail, rollouts))
    (ref_mean, ref_costs, ref_fail, ref), (jit_mean, jit_costs, jit_fail, jit) = outputs
    assert np.abs(ref_costs).sum(axis=1).min() >= 0.0
    for name in ("cvx", "cvy", "cwz", "vx", "vy", "wz", "x", "y", "yaw"):
        np.testing.assert_allclose(getattr(jit, name), getattr(ref, name), rtol=0, atol=1e-11, err_msg=name)
    for k, (name, _) in enumerate(critics):
        np.testing.assert_allclose(jit_costs[k], ref_costs[k], rtol=1e-9, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(jit_mean, ref_mean, rtol=1e-9, atol=1e-12)
    assert jit_fail == ref_fail


def test_the_cases_exercise_every_critic() -> None:
    """Each critic costs something in at least one case, so the agreement above is not vacuous."""
    active: set[str] = set()
    for case in CASES:
        c = CASES[case]
        params = MPPIParams(batch_size=BATCH, time_steps=STEPS, critics=tuple(CRITIC_PARAMS),
                            motion_model=str(c.get("model", "DiffDrive")))
        critics = _critics(PathAngleCritic={"mode": c.get("mode", 0), "offset_from_furthest": 10},
                           PathAlignCritic={"offset_from_furthest": 2})
        grid = costmap(window(), [(0.5, 0.3, 0.8, 0.6), (0.9, -0.7, 1.1, -0.4), (-0.6, -0.2, -0.5, 0.2)])
        path = in_window(polyline([(0.0, 0.0), (0.8, 0.1), (1.2, -0.2), (1.4, 0.0)]), grid)
        scene = Scene.make(c["robot"], c["speed"], path, path[-1], grid, FootprintModel.of(
            CircleFootprint(0.22), 0.22, INFLATION))
        rng = np.random.default_rng(3)
        noise = NoiseGenerator(rng, BATCH, STEPS, holonomic=True).noise
        _, costs, _ = JitKernels(params, critics, 0.3).iterate(np.zeros((3, STEPS)), noise, scene,
                                                              Rollouts.empty(BATCH, STEPS))
        active |= {name for k, (name, _) in enumerate(critics) if np.ptp(costs[k]) > 0.0}
    assert active == set(CRITIC_PARAMS)


def test_every_trajectory_colliding_sets_the_fail_flag_in_both() -> None:
    grid = costmap(window(), [(-1.5, -1.5, 1.5, 1.5)])  # lethal everywhere
    path = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]])
    scene = Scene.make(Pose2D(0.0, 0.0, 0.0), Twist2D(0.0, 0.0), path, path[-1], grid, FootprintModel())
    params = MPPIParams(batch_size=50, time_steps=30)
    noise = NoiseGenerator(np.random.default_rng(0), 50, 30, holonomic=False).noise
    for kernels in (ReferenceKernels, JitKernels):
        _, _, fail = kernels(params, _critics(), 0.2).iterate(np.zeros((3, 30)), noise, scene,
                                                            Rollouts.empty(50, 30))
        assert fail, kernels.__name__


def test_the_compiled_noise_is_standard_normal_and_repeats_with_the_seed() -> None:
    out = np.zeros(400_000, dtype=np.float32)
    standard_normal_fast(np.random.default_rng(11), out)
    assert abs(out.mean()) < 0.01 and abs(out.std() - 1.0) < 0.01
    for z, tail in ((1.0, 0.3173), (2.0, 0.0455), (3.0, 0.0027)):
        assert abs(np.mean(np.abs(out) > z) - tail) < 0.1 * tail + 5e-4, z
    xs = np.sort(out[:100_000].astype(np.float64))
    cdf = 0.5 * (1.0 + np.array([math.erf(v / math.sqrt(2.0)) for v in xs[::50]]))
    assert np.max(np.abs(cdf - (np.arange(0, len(xs), 50) + 1) / len(xs))) < 0.006  # Kolmogorov-Smirnov
    again = np.zeros(400_000, dtype=np.float32)
    standard_normal_fast(np.random.default_rng(11), again)
    assert np.array_equal(out, again)


def test_the_compiled_controller_sends_the_reference_commands_for_the_same_noise() -> None:
    """Whole cycles (path cut, iteration, smoothing, clamps, shift) with the same seeded noise: the
    compiled backend's commands and control sequence are the numpy reference's."""
    params = MPPIParams(batch_size=BATCH, time_steps=STEPS)
    path = polyline([(0.0, 0.0), (0.6, 0.0), (1.0, 0.5), (1.0, 1.5)])
    controllers = [MPPIController(params, inflation=INFLATION, kernels=kind) for kind in ("reference", "jit")]
    for controller in controllers:  # the same noise stream for both
        controller.optimizer.noise = NoiseGenerator(np.random.default_rng(21), BATCH, STEPS, holonomic=False)
        controller.reset()
    robot, velocity = Pose2D(0.0, 0.05, 0.4), Twist2D(0.0, 0.0)
    for _ in range(15):
        grid = costmap(window(robot.x, robot.y), [(0.3, 0.4, 0.5, 0.6)])
        local = in_window(nearest_on(path, robot), grid)
        ref, fast = (c.compute_velocity(robot, velocity, local, grid) for c in controllers)
        assert fast == pytest.approx(ref, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(controllers[1].optimizer.sequence, controllers[0].optimizer.sequence,
                                   rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(controllers[1].last_trajectory, controllers[0].last_trajectory,
                                   rtol=1e-9, atol=1e-12)
        robot, velocity = step(robot, ref, 0.05), ref
    assert robot.x > 0.05  # it moved along the path: the cycles were not trivial


def test_the_compiled_smoothing_is_nav2s_savitzky_golay_filter() -> None:
    rng = np.random.default_rng(4)
    sequence, history = rng.normal(size=(3, STEPS)), rng.normal(size=(sequence_jit.HISTORY, 3))
    expected = sequence.copy()
    for axis in range(3):
        padded = np.concatenate([history[:, axis], sequence[axis], np.full(4, sequence[axis, -1])])
        expected[axis, :-1] = np.convolve(padded, sequence_jit.SGF_WEIGHTS[::-1], mode="valid")[: STEPS - 1]
    smoothed = sequence.copy()
    sequence_jit.smooth(smoothed, history, sequence_jit.SGF_WEIGHTS)
    np.testing.assert_allclose(smoothed, expected, rtol=1e-12, atol=1e-14)
    short = sequence[:, : sequence_jit.SGF_MIN_STEPS - 1].copy()
    sequence_jit.smooth(short, history, sequence_jit.SGF_WEIGHTS)
    np.testing.assert_array_equal(short, sequence[:, : sequence_jit.SGF_MIN_STEPS - 1])  # Nav2: unfiltered


def test_the_optimal_trajectory_is_integrated_as_the_rollouts_are() -> None:
    sequence = np.random.default_rng(8).normal(0.0, 0.3, (3, STEPS))
    robot = Pose2D(0.3, -0.2, 1.1)
    x, y, yaw = poses(sequence[0:1], sequence[1:2], sequence[2:3], robot, 0.05)
    np.testing.assert_allclose(sequence_jit.drive(sequence, robot.x, robot.y, robot.yaw, 0.05),
                               np.column_stack([x[0], y[0], yaw[0]]), rtol=0, atol=1e-13)
