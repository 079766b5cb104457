"""The compiled lidar caster (lidar_jit.BinnedCaster) returns cast_rays' ranges, the reference's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim2d.core.geometry import StaticGeometry, regular_polygon
from sim2d.core.lidar import Lidar, LidarParams, cast_rays
from sim2d.core.lidar_jit import BinnedCaster, BinnedGeometry
from sim2d.core.world import load_world


def random_world(rng: np.random.Generator) -> StaticGeometry:
    """Boxes, circles, convex polygons and long walls scattered over 40 x 25 m."""
    corners = rng.uniform((-20.0, -12.0), (18.0, 10.0), size=(60, 2))
    boxes = np.column_stack([corners, corners + rng.uniform(0.05, 3.0, size=(60, 2))])
    boxes = np.vstack([boxes, [[-21.0, -13.0, 21.0, -12.8], [-21.0, 12.8, 21.0, 13.0]]])  # long walls
    circles = np.column_stack([rng.uniform((-20.0, -12.0), (20.0, 12.0), size=(25, 2)),
                               rng.uniform(0.05, 1.0, 25)])
    centres = rng.uniform((-18.0, -10.0), (18.0, 10.0), size=(15, 2))
    polygons = tuple(regular_polygon((float(x), float(y)), float(rng.uniform(0.2, 2.0)),
                                     int(rng.integers(3, 9)), float(rng.uniform(0.0, math.pi)))
                     for x, y in centres)
    return StaticGeometry(circles=circles, boxes=boxes, polygons=polygons)


@pytest.mark.parametrize("seed", range(6))
def test_compiled_caster_agrees_with_the_reference_on_random_worlds(seed: int) -> None:
    rng = np.random.default_rng(seed)
    geometry = random_world(rng)
    caster = BinnedCaster()
    for _ in range(15):
        origin = (float(rng.uniform(-25.0, 25.0)), float(rng.uniform(-16.0, 16.0)))  # also outside, inside
        angles = rng.uniform(-math.pi, 3.0 * math.pi, 360)
        angles[:4] = (0.0, math.pi / 2, math.pi, -math.pi / 2)  # axis-parallel beams
        max_range = float(rng.choice([3.5, 12.0, 60.0]))
        expected = cast_rays(origin, angles, geometry, max_range)
        got = caster(origin, angles, geometry, max_range)
        assert np.array_equal(np.isinf(got), np.isinf(expected)), f"hit / no hit differs at {origin}"
        assert got[np.isfinite(got)] == pytest.approx(expected[np.isfinite(expected)], abs=1e-12)
        assert np.count_nonzero(np.isfinite(expected)) > 0 or max_range < 60.0


def test_compiled_caster_agrees_on_the_shipped_worlds() -> None:
    rng = np.random.default_rng(7)
    for name in ("turtlebot3_world", "depot_large"):
        geometry = load_world(name).geometry
        caster = BinnedCaster()
        low, high = geometry.ray_segments[:, :2].min(axis=0), geometry.ray_segments[:, :2].max(axis=0)
        for x, y in rng.uniform(low, high, size=(20, 2)):
            angles = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False) + rng.uniform(0.0, 0.1)
            expected = cast_rays((x, y), angles, geometry, 12.0)
            got = caster((x, y), angles, geometry, 12.0)
            assert np.array_equal(np.isinf(got), np.isinf(expected))
            assert got[np.isfinite(got)] == pytest.approx(expected[np.isfinite(expected)], abs=1e-12)


def test_bins_are_refiled_when_the_geometry_changes() -> None:
    caster = BinnedCaster()
    empty = StaticGeometry()
    assert np.isposinf(caster((0.0, 0.0), np.array([0.0]), empty, 5.0)).all()
    assert BinnedGeometry.of(empty).nx >= 1
    with_circle = StaticGeometry(circles=np.array([[2.0, 0.0, 0.5]]))  # as Simulator.add_circle replaces it
    assert caster((0.0, 0.0), np.array([0.0]), with_circle, 5.0)[0] == pytest.approx(1.5)


def test_lidar_casts_compiled_by_default_and_accepts_the_reference() -> None:
    geometry = StaticGeometry(boxes=np.array([[1.0, -1.0, 2.0, 1.0]]))
    params = LidarParams(noise_stddev=0.0)
    compiled = Lidar(params, geometry, np.random.default_rng(0))
    reference = Lidar(params, geometry, np.random.default_rng(0), caster=cast_rays)
    assert isinstance(compiled._cast, BinnedCaster)
    assert np.array_equal(compiled.scan(0.0, 0.0, 0.3), reference.scan(0.0, 0.0, 0.3))
