"""The obstacle layer reports only the cells its scans changed, and that loses nothing.

A costmap redrawing only those windows must hold, after every update, the grid a twin redrawing its
whole grid each update holds; a scan that changes nothing (the same scan from the same pose) redraws
nothing.
"""

from __future__ import annotations

import math

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
)
from nav_stack.core.grid import GridSpec


def _costmap(params: CostmapParams) -> tuple[LayeredCostmap, ObstacleLayer]:
    obstacle = ObstacleLayer(params)
    layers = [StaticLayer(params), obstacle, InflationLayer(InflationLayerParams(inflation_radius=0.5))]
    return LayeredCostmap(params, layers), obstacle


@pytest.mark.parametrize("seed", range(5))
def test_windowed_updates_equal_whole_grid_redraws(seed: int) -> None:
    rng = np.random.default_rng(seed)
    spec = GridSpec(160, 120, 0.05, -1.0, -2.0)
    params = CostmapParams(track_unknown_space=seed % 2 == 0, footprint_padding=0.0)
    occupancy = np.where(rng.random(spec.shape) < 0.01, 100, 0).astype(np.int8)
    windowed, whole = _costmap(params), _costmap(params)
    for costmap, _ in (windowed, whole):
        costmap.set_map(occupancy, spec)
    for _ in range(12):
        pose = (float(rng.uniform(0.0, 6.0)), float(rng.uniform(-1.0, 3.0)), float(rng.uniform(-3.0, 3.0)))
        beams = 90
        ranges = rng.uniform(0.2, 4.0, beams)
        ranges[rng.random(beams) < 0.2] = np.inf
        scan = LaserScan(ranges, -math.pi, 2 * math.pi / beams, 0.12, 3.5)
        windowed[1].add_scan(scan, pose)
        windowed[0].update(pose)
        whole[1].add_scan(scan, pose)
        whole[0].redraw_all()
        whole[0].update(pose)
        np.testing.assert_array_equal(windowed[0].costs, whole[0].costs)
        np.testing.assert_array_equal(windowed[1].grid, whole[1].grid)


def test_a_scan_that_changes_nothing_redraws_nothing() -> None:
    spec = GridSpec(200, 200, 0.03)
    params = CostmapParams(resolution=0.03)
    costmap, obstacle = _costmap(params)
    costmap.set_map(np.zeros(spec.shape, dtype=np.int8), spec)
    pose = (3.0, 3.0, 0.0)
    costmap.update(pose)
    scan = LaserScan(np.full(360, 1.5), 0.0, 2 * math.pi / 360, 0.12, 3.5)
    obstacle.add_scan(scan, pose)
    first = costmap.update(pose)
    assert not first.is_empty and first.x1 - first.x0 < spec.width  # the ring and its inflation
    obstacle.add_scan(scan, pose)
    assert costmap.update(pose).is_empty
