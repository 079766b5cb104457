"""Odometry drift: ideal mode is exact; noisy mode has the configured error statistics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim2d.core.odometry import Odometry, OdometryParams
from sim2d.core.robot import Pose2D
from tests.unit.sim2d.conftest import drive


def test_ideal_odometry_equals_ground_truth_relative_to_spawn(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 0.0), odometry=OdometryParams(ideal=True))
    drive(sim, 0.2, 0.4, 3.0)
    drive(sim, -0.1, -0.8, 1.0)
    assert (sim.odometry.pose.x, sim.odometry.pose.y, sim.odometry.pose.yaw) == pytest.approx(
        (sim.pose.x + 2.0, sim.pose.y + 0.5, sim.pose.yaw), abs=1e-9)


def _straight_metre(params: OdometryParams, runs: int, steps: int) -> np.ndarray:
    rng = np.random.default_rng(21)
    finals = []
    for _ in range(runs):
        odom = Odometry(params, rng)
        for _ in range(steps):
            odom.update(1.0 / steps, 0.0, 0.0)
        finals.append((odom.pose.x, odom.pose.y, odom.pose.yaw))
    return np.array(finals)


@pytest.mark.parametrize("steps", [50, 200])
def test_drift_per_metre_matches_coefficients_for_any_step(steps: int) -> None:
    params = OdometryParams(trans_from_trans=0.03, rot_from_trans=0.05, trans_from_rot=0.0, rot_from_rot=0.0)
    finals = _straight_metre(params, 600, steps)
    assert np.std(finals[:, 0]) == pytest.approx(0.03, rel=0.1)        # along-track σ after 1 m
    assert np.std(finals[:, 2]) == pytest.approx(0.05, rel=0.1)        # heading σ after 1 m
    # lateral error integrates the heading random walk: σ_y = σ_θ / √3 after 1 m
    assert np.std(finals[:, 1]) == pytest.approx(0.05 / math.sqrt(3.0), rel=0.12)


def test_rotation_in_place_drift_matches_coefficient() -> None:
    params = OdometryParams(rot_from_rot=0.04)
    rng = np.random.default_rng(3)
    yaws = []
    for _ in range(600):
        odom = Odometry(params, rng)
        for _ in range(100):
            odom.update(0.0, 0.0, math.pi / 100)              # half a turn: |θ| = π
        yaws.append(odom.pose.yaw - (-math.pi if odom.pose.yaw < 0 else math.pi))
    assert np.std(yaws) == pytest.approx(0.04 * math.sqrt(math.pi), rel=0.1)


def test_default_drift_needs_a_localizer(make_sim) -> None:
    errors = []
    for seed in range(8):
        sim = make_sim(Pose2D(-2.0, -0.5, 0.0), seed=seed)
        drive(sim, 0.2, 0.0, 5.0)                               # about one metre
        odom, truth = sim.odometry.pose, sim.pose
        errors.append(math.hypot(odom.x - (truth.x + 2.0), odom.y - (truth.y + 0.5)))
    assert 0.005 < float(np.median(errors)) < 0.1
