"""Lidar: ranges match the geometry, REP 117 conventions, noise and dropout as configured."""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest

from sim2d.core.collision import build_space
from sim2d.core.lidar import LidarParams, cast_rays
from sim2d.core.robot import WAFFLE, Pose2D


def test_beam_layout_is_lds01() -> None:
    p = LidarParams()
    assert (p.beams, p.angle_min, p.range_min, p.range_max, p.rate, p.noise_stddev) == \
        (360, 0.0, 0.12, 3.5, 5.0, 0.01)
    assert p.angle_increment == pytest.approx(math.radians(1.0))
    assert p.angle_max == pytest.approx(math.radians(359.0))


def test_scan_at_known_pose_matches_analytic_distances(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0 - WAFFLE.scan_offset[0], -1.1, 0.0), lidar=LidarParams(noise_stddev=0.0))
    ranges = sim.scan()                                   # sensor exactly at (-2.0, -1.1), facing +x
    assert ranges[0] == pytest.approx(0.9 - 0.15, abs=1e-9)          # pillar (-1.1, -1.1) ahead
    # lower-left wall: inner edge from (-2.933, 0) to (-1.4665, -2.54); beam 180° hits it at y = -1.1
    wall_x = -2.933 + 1.1 / math.tan(math.radians(60.0))
    assert ranges[180] == pytest.approx(-2.0 - wall_x, abs=1e-3)
    # straight down and up, the slanted walls y = ∓(x + 2.933)·√3 at x = -2.0
    wall_y = (-2.0 + 2.933) * math.sqrt(3.0)
    assert ranges[270] == pytest.approx(wall_y - 1.1, abs=1e-3)
    assert ranges[90] == pytest.approx(wall_y + 1.1, abs=1e-3)


def test_scan_agrees_with_pymunk_ray_queries(tb3_world) -> None:
    space = build_space(tb3_world.geometry)
    rng = np.random.default_rng(4)
    angles = np.linspace(0.0, 2.0 * math.pi, 90, endpoint=False)
    for x, y in rng.uniform((-2.0, -1.8), (2.0, 1.8), size=(6, 2)):
        if tb3_world.geometry.contains(np.array([[x, y]]))[0]:
            continue
        ours = cast_rays((x, y), angles, tb3_world.geometry, 20.0)
        for angle, r in zip(angles, ours, strict=True):
            end = (x + 20.0 * math.cos(angle), y + 20.0 * math.sin(angle))
            hit = space.segment_query_first((x, y), end, 0.0, pymunk.ShapeFilter())
            expected = math.inf if hit is None else hit.alpha * 20.0
            assert r == pytest.approx(expected, abs=1e-6)


def test_out_of_range_is_inf_and_too_close_is_minus_inf(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 0.0), lidar=LidarParams(noise_stddev=0.0, range_max=1.0, range_min=0.7))
    ranges = sim.scan()
    assert np.isposinf(ranges[0])                        # nothing within 1 m straight ahead
    assert np.isneginf(ranges[180])                      # wall behind at 0.58 m < range_min
    finite = ranges[np.isfinite(ranges)]
    assert np.all((finite >= 0.7) & (finite <= 1.0))


def test_noise_has_the_configured_stddev(make_sim) -> None:
    exact = make_sim(lidar=LidarParams(noise_stddev=0.0)).scan()
    noisy = make_sim(lidar=LidarParams(noise_stddev=0.02), seed=5)
    hits = np.isfinite(exact) & (exact < 3.3)
    errors = np.concatenate([noisy.scan()[hits] - exact[hits] for _ in range(50)])
    assert np.std(errors) == pytest.approx(0.02, rel=0.05)
    assert abs(np.mean(errors)) < 0.002


def test_dropout_probability_gives_that_share_of_inf(make_sim) -> None:
    sim = make_sim(lidar=LidarParams(noise_stddev=0.0, dropout_probability=0.25, range_max=20.0))
    ranges = np.concatenate([sim.scan() for _ in range(40)])
    assert np.mean(np.isposinf(ranges)) == pytest.approx(0.25, abs=0.02)


def test_bad_lidar_parameter_is_named() -> None:
    with pytest.raises(ValueError, match=r"lidar\.range_max"):
        LidarParams(range_min=1.0, range_max=0.5)
