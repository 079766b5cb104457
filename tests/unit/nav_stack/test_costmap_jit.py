"""The compiled inflation (inflation_jit, distance_jit) gives the numpy reference's costmaps cell for cell."""

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
)
from nav_stack.core.grid import GridSpec


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
    """The same costmap twice: compiled inflation, then the reference."""
    pair = []
    for inflate in (None, inflation_layer.inflate):
        obstacle = ObstacleLayer(params)
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
