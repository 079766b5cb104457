"""The compiled kernels (inflation_jit, distance_jit, raytrace_jit) give the numpy references' costmaps cell
for cell."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from nav_stack.core.costmap import (
    CostmapParams,
    InflationLayer,
    InflationLayerParams,
    LaserScan,
    LayeredCostmap,
    ObstacleLayer,
    StaticLayer,
    inflation_layer,
    raytrace,
    raytrace_jit,
)
from nav_stack.core.grid import FREE_SPACE, GridSpec


def _random_occupancy(rng: np.random.Generator, width: int, height: int) -> np.ndarray:
    """Boxes of obstacles, unknown patches, graded values between them (OccupancyGrid values)."""
    occ = rng.choice(np.array([0, 0, 0, 30, 70], dtype=np.int8), size=(height, width))
    for _ in range(width * height // 150):
        x, y = int(rng.integers(0, width)), int(rng.integers(0, height))
        w, h = (int(n) for n in rng.integers(1, 8, size=2))
        occ[y : y + h, x : x + w] = 100 if rng.random() < 0.7 else -1
    return occ


def _random_scan(rng: np.random.Generator) -> LaserScan:
    beams = int(rng.integers(10, 120))
    ranges = rng.uniform(0.05, 4.0, beams)
    ranges[rng.random(beams) < 0.1] = np.inf
    return LaserScan(ranges, float(rng.uniform(-math.pi, math.pi)), 2 * math.pi / beams, 0.12, 3.5)


def _costmap_pair(params: CostmapParams, inflation: InflationLayerParams, static: bool
                  ) -> list[tuple[LayeredCostmap, ObstacleLayer]]:
    """The same costmap twice: compiled inflation and ray clearing, then the references."""
    pair = []
    for inflate, clear_rays in ((None, None), (inflation_layer.inflate, raytrace.clear_rays)):
        obstacle = ObstacleLayer(params, clear_rays=clear_rays)
        layers = [StaticLayer(params)] if static else []
        pair.append((LayeredCostmap(params, [*layers, obstacle, InflationLayer(inflation, inflate=inflate)]),
                     obstacle))
    return pair


@pytest.mark.parametrize("seed", range(10))
def test_compiled_inflation_gives_the_reference_costmap(seed: int) -> None:
    """Full and incremental updates of a static + obstacle + inflation costmap, random maps and scans."""
    rng = np.random.default_rng(seed)
    width, height = (int(n) for n in rng.integers(20, 140, size=2))
    resolution = float(rng.choice([0.03, 0.05, 0.1]))
    spec = GridSpec(width, height, resolution, -1.0, -0.5)
    robot_radius = float(rng.uniform(0.1, 0.3))
    params = CostmapParams(robot_radius=robot_radius, trinary_costmap=seed % 3 != 0,
                           track_unknown_space=seed % 4 != 0)
    inflation = InflationLayerParams(inflation_radius=robot_radius + float(rng.uniform(0.1, 0.7)),
                                     cost_scaling_factor=float(rng.uniform(0.5, 6.0)),
                                     inflate_unknown=seed % 2 == 0)
    pair = _costmap_pair(params, inflation, static=True)
    occupancy = _random_occupancy(rng, width, height)
    for costmap, _ in pair:
        costmap.set_map(occupancy, spec)
    for _ in range(5):
        x, y = spec.cell_to_world(int(rng.integers(0, width)), int(rng.integers(0, height)))
        pose = (float(x), float(y), float(rng.uniform(-math.pi, math.pi)))
        scan = _random_scan(rng)
        windows = []
        for costmap, obstacle in pair:
            obstacle.add_scan(scan, pose)
            windows.append(costmap.update(pose))
        (compiled, _), (reference, _) = pair
        assert windows[0] == windows[1]
        np.testing.assert_array_equal(compiled.costs, reference.costs)
    decayed = (compiled.costs > 0) & (compiled.costs < 253) & (occupancy == 0)
    assert (compiled.costs == 254).any() and decayed.any()  # the maps exercise every rule


def test_compiled_inflation_of_a_radius_over_127_cells_gives_the_reference_costmap() -> None:
    """Its int32 work arrays (distance_jit.work_dtype), on a sparse map at 1 cm."""
    rng = np.random.default_rng(11)
    spec = GridSpec(160, 90, 0.01)
    pair = _costmap_pair(CostmapParams(resolution=0.01), InflationLayerParams(inflation_radius=1.5),
                         static=True)
    occupancy = np.zeros(spec.shape, dtype=np.int8)
    occupancy[rng.random(spec.shape) < 0.001] = 100
    occupancy[60:, :30] = -1
    for costmap, _ in pair:
        costmap.set_map(occupancy, spec)
        costmap.update((0.5, 0.5, 0.0))
    inflation = pair[0][0].layers[-1]
    assert isinstance(inflation, InflationLayer) and inflation.radius_cells == 150
    np.testing.assert_array_equal(pair[0][0].costs, pair[1][0].costs)


@pytest.mark.parametrize("seed", range(4))
def test_compiled_inflation_gives_the_reference_rolling_costmap(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    params = replace(CostmapParams.local_defaults(), track_unknown_space=seed % 2 == 0)
    pair = _costmap_pair(params, InflationLayerParams(), static=False)
    pose = (0.0, 0.0, 0.0)
    for _ in range(6):
        pose = (pose[0] + float(rng.uniform(-0.3, 0.3)), pose[1] + float(rng.uniform(-0.3, 0.3)), 0.0)
        scan = _random_scan(rng)
        for costmap, obstacle in pair:
            obstacle.add_scan(scan, pose)
            costmap.update(pose)
        np.testing.assert_array_equal(pair[0][0].costs, pair[1][0].costs)


@pytest.mark.parametrize("seed", range(10))
def test_compiled_ray_clearing_gives_the_reference_grid_and_window(seed: int) -> None:
    """Random grids (some rotated), sensors on and off the grid, rays of every length, a minimum range."""
    rng = np.random.default_rng(seed)
    width, height = (int(n) for n in rng.integers(5, 90, size=2))
    yaw = float(rng.choice([0.0, rng.uniform(-math.pi, math.pi)]))
    spec = GridSpec(width, height, float(rng.choice([0.03, 0.05, 0.1])), -0.7, 0.4, yaw)
    for _ in range(20):
        origin = (float(rng.uniform(-2.0, 4.0)), float(rng.uniform(-1.0, 5.0)))
        beams = int(rng.integers(0, 200))
        lengths = rng.uniform(0.0, 5.0, beams)
        lengths[rng.random(beams) < 0.1] = 0.0
        angles = rng.uniform(-math.pi, math.pi, beams)
        min_length = float(rng.choice([0.0, rng.uniform(0.0, 1.0)]))
        start = rng.integers(0, 255, size=spec.shape, dtype=np.uint8)
        compiled, reference = start.copy(), start.copy()
        window = raytrace_jit.clear_rays(compiled, spec, origin, lengths, angles, min_length, FREE_SPACE)
        expected = raytrace.clear_rays(reference, spec, origin, lengths, angles, min_length, FREE_SPACE)
        np.testing.assert_array_equal(compiled, reference)
        assert window == expected


def test_ray_clearing_frees_the_beam_but_not_its_return_nor_the_minimum_range() -> None:
    """One beam along +x from cell (1, 2) of a 1 m grid, 5 m long, clearing from 1.5 m on."""
    grid = np.full((5, 8), 100, dtype=np.uint8)
    window = raytrace_jit.clear_rays(grid, GridSpec(8, 5, 1.0), (1.5, 2.5), np.array([5.0]), np.array([0.0]),
                                     1.5, FREE_SPACE)
    assert np.flatnonzero(grid[2] == FREE_SPACE).tolist() == [3, 4, 5]  # 2: under 1.5 m; 6: the return
    assert (grid[[0, 1, 3, 4]] == 100).all()
    assert (window.x0, window.y0, window.x1, window.y1) == (3, 2, 6, 3)  # the cells it changed
    assert raytrace_jit.clear_rays(grid, GridSpec(8, 5, 1.0), (1.5, 2.5), np.array([5.0]), np.array([0.0]),
                                   1.5, FREE_SPACE).is_empty  # all free already: nothing changed
