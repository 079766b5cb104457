"""Layered costmap: static/obstacle/inflation layers, rolling window, footprint checks (Nav2 semantics)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from nav_stack.core.costmap import (
    CostmapParams,
    Footprint,
    InflationLayer,
    InflationLayerParams,
    LaserScan,
    LayeredCostmap,
    ObstacleLayer,
    ObstacleLayerParams,
    StaticLayer,
    costs_from_occupancy,
    footprint_cost,
    footprint_costs,
    inflation_cost,
)
from nav_stack.core.costmap.distance import squared_distance_cells
from nav_stack.core.grid import GridSpec
from navsuite_testing.nav.fake_lidar import fake_scan, pillar_world

SQUARE = ((0.22, 0.22), (0.22, -0.22), (-0.22, -0.22), (-0.22, 0.22))  # inscribed radius exactly 0.22 m


def square_params(**overrides: object) -> CostmapParams:
    return replace(CostmapParams(footprint=SQUARE, footprint_padding=0.0), **overrides)


def one_beam(rng: float, angle: float = 0.0, range_max: float = 3.5) -> LaserScan:
    return LaserScan(np.array([rng]), angle, 0.01, 0.12, range_max)


def test_static_layer_interprets_occupancy_like_nav2() -> None:
    occ = np.array([[-1, 0, 50, 99, 100]], dtype=np.int8)
    tracked = costs_from_occupancy(occ, CostmapParams(track_unknown_space=True))
    assert tracked.tolist() == [[255, 0, 0, 0, 254]]
    untracked = costs_from_occupancy(occ, CostmapParams(track_unknown_space=False))
    assert untracked.tolist() == [[0, 0, 0, 0, 254]]
    scaled = costs_from_occupancy(occ, CostmapParams(trinary_costmap=False, lethal_cost_threshold=100))
    assert scaled.tolist() == [[255, 0, 127, 251, 254]]
    low = costs_from_occupancy(occ, CostmapParams(lethal_cost_threshold=50))
    assert low.tolist() == [[255, 0, 254, 254, 254]]


def test_inflation_formula_matches_documented_values() -> None:
    # r_in = 0.22, csf 3: 0.30 m → 198, 0.45 m → 126, 0.70 m → 59 (reference/nav2.md §4).
    costs = inflation_cost([0.0, 0.1, 0.22, 0.30, 0.45, 0.70], 0.22, 3.0)
    assert costs.tolist() == [254, 253, 253, 198, 126, 59]


def _single_obstacle_costmap(
    params: CostmapParams, inflation: InflationLayerParams | None = None
) -> LayeredCostmap:
    spec = GridSpec(41, 41, 0.05, -1.0, -1.0)
    occ = np.zeros(spec.shape, dtype=np.int8)
    occ[20, 20] = 100
    costmap = LayeredCostmap(params, [StaticLayer(params), InflationLayer(inflation)])
    costmap.set_map(occ, spec)
    costmap.update((0.0, 0.0, 0.0))
    return costmap


def test_inflation_around_one_lethal_cell_follows_nav2_formula() -> None:
    costmap = _single_obstacle_costmap(square_params())
    assert costmap.inscribed_radius == pytest.approx(0.22)
    c = costmap.costs
    assert c[20, 20] == 254
    assert c[20, 24] == 253  # 0.20 m ≤ inscribed radius
    assert c[20, 26] == 198  # 0.30 m
    assert c[23, 24] == math.floor(252 * math.exp(-3.0 * (0.25 - 0.22)))  # (3, 4) cells → 0.25 m
    assert c[20, 29] == 126  # 0.45 m
    assert c[20, 34] == 59  # 0.70 m = 14 cells, the last inflated ring
    assert c[20, 35] == 0  # 15 cells
    gy, gx = np.mgrid[0:41, 0:41]
    d = np.hypot(gx - 20, gy - 20) * 0.05
    expected = np.where(np.hypot(gx - 20, gy - 20) <= 14, inflation_cost(d, 0.22, 3.0), 0)
    assert np.array_equal(c, expected)


def test_round_footprint_radii_follow_nav2_padding() -> None:
    fp = Footprint.from_params(CostmapParams())  # robot_radius 0.22, padding 0.01
    assert fp.points.shape == (16, 2)
    assert fp.circumscribed_radius == pytest.approx(
        math.hypot(0.22 * math.cos(math.pi / 4) + 0.01, 0.22 * math.cos(math.pi / 4) + 0.01)
    )
    assert 0.22 * math.cos(math.pi / 16) < fp.inscribed_radius < 0.23


def test_unknown_cells_take_only_lethal_or_inscribed_inflation_unless_inflate_unknown() -> None:
    params = square_params()
    spec = GridSpec(21, 1, 0.05)
    occ = np.full(spec.shape, -1, dtype=np.int8)
    occ[0, 0] = 100
    costmap = LayeredCostmap(params, [StaticLayer(params), InflationLayer()])
    costmap.set_map(occ, spec)
    costmap.update((0.5, 0.02, 0.0))
    assert costmap.costs[0, :7].tolist() == [254, 253, 253, 253, 253, 255, 255]
    eager = LayeredCostmap(
        params, [StaticLayer(params), InflationLayer(InflationLayerParams(inflate_unknown=True))]
    )
    eager.set_map(occ, spec)
    eager.update((0.5, 0.02, 0.0))
    assert eager.costs[0, 5] == math.floor(252 * math.exp(-3.0 * (0.25 - 0.22)))
    assert eager.costs[0, 20] == 255  # beyond the inflation radius


def _obstacle_costmap(**layer_overrides: object) -> tuple[LayeredCostmap, ObstacleLayer]:
    params = square_params(track_unknown_space=True)
    layer = ObstacleLayer(params, ObstacleLayerParams(footprint_clearing_enabled=False, **layer_overrides))
    costmap = LayeredCostmap(params, [layer], GridSpec(100, 20, 0.05, 0.0, 0.0))
    return costmap, layer


def test_obstacle_layer_marks_endpoint_and_clears_the_ray() -> None:
    costmap, layer = _obstacle_costmap()
    layer.add_scan(one_beam(1.0), (0.025, 0.525, 0.0))
    costmap.update((0.025, 0.525, 0.0))
    row = costmap.costs[10]
    assert row[20] == 254  # x = 1.0 m
    assert (row[:20] == 0).all()  # cleared between sensor and return
    assert (row[21:] == 255).all()  # never seen
    assert (costmap.costs[5] == 255).all()
    # The obstacle moves away: the old mark is cleared by the new ray, the new return is marked.
    layer.add_scan(one_beam(2.0), (0.025, 0.525, 0.0))
    costmap.update((0.025, 0.525, 0.0))
    assert costmap.costs[10, 20] == 0 and costmap.costs[10, 40] == 254


def test_obstacle_ranges_limit_marking_and_clearing() -> None:
    costmap, layer = _obstacle_costmap(obstacle_max_range=2.5, raytrace_max_range=3.0, raytrace_min_range=0.5)
    layer.add_scan(one_beam(2.7), (0.025, 0.525, 0.0))
    costmap.update((0.025, 0.525, 0.0))
    row = costmap.costs[10]
    assert row[53] == 0 and not (row == 254).any()  # beyond obstacle_max_range: cleared, not marked
    assert (row[:10] == 255).all() and (row[10:54] == 0).all()  # raytrace_min_range keeps the first 0.5 m


def test_invalid_and_infinite_readings() -> None:
    costmap, layer = _obstacle_costmap()
    layer.add_scan(LaserScan(np.array([np.nan, 3.5, np.inf, 0.05]), 0.0, 0.0, 0.12, 3.5), (0.025, 0.525, 0.0))
    costmap.update((0.025, 0.525, 0.0))
    assert (costmap.costs == 255).all()  # NaN, ≥ range_max, inf (not valid) and < range_min are dropped
    costmap2, layer2 = _obstacle_costmap(inf_is_valid=True)
    layer2.add_scan(LaserScan(np.array([np.inf]), 0.0, 0.0, 0.12, 2.0), (0.025, 0.525, 0.0))
    costmap2.update((0.025, 0.525, 0.0))
    assert (costmap2.costs[10, :39] == 0).all() and not (costmap2.costs == 254).any()


def test_footprint_clearing_frees_cells_under_the_robot() -> None:
    params = square_params(track_unknown_space=True)
    layer = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [layer], GridSpec(100, 20, 0.05))
    layer.add_scan(one_beam(2.0), (0.025, 0.525, 0.0))  # marks x ≈ 2.0 m
    costmap.update((0.025, 0.525, 0.0))
    assert costmap.costs[10, 40] == 254
    costmap.update((2.0, 0.525, 0.0))  # the robot now stands there: the mark cannot be real
    assert costmap.costs[10, 40] == 0


def test_rolling_window_recentres_and_keeps_obstacles_in_place() -> None:
    params = replace(CostmapParams.local_defaults(), footprint=SQUARE, footprint_padding=0.0)
    layer = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [layer, InflationLayer()])
    assert costmap.spec.shape == (60, 60)
    costmap.update((0.0, 0.0, 0.0))
    assert costmap.spec.origin_x == pytest.approx(-1.5) and costmap.spec.origin_y == pytest.approx(-1.5)
    layer.add_scan(one_beam(1.0, angle=0.2), (0.0, 0.0, 0.0))
    costmap.update((0.0, 0.0, 0.0))
    ox, oy = 1.0 * math.cos(0.2), 1.0 * math.sin(0.2)
    mx, my = costmap.spec.world_to_cell(ox, oy)
    assert costmap.costs[my, mx] == 254
    costmap.update((0.52, -0.31, 0.0))
    assert costmap.spec.origin_x == pytest.approx(-1.5 + 0.50) and costmap.spec.origin_y == pytest.approx(
        -1.5 - 0.30
    )
    mx2, my2 = costmap.spec.world_to_cell(ox, oy)
    assert (int(mx2), int(my2)) == (int(mx) - 10, int(my) + 6)
    assert costmap.costs[my2, mx2] == 254
    assert (costmap.costs == 254).sum() == 1
    assert costmap.costs[my2, mx2 - 4] == 253  # inflation moved with it
    costmap.update((5.0, 0.0, 0.0))
    assert (costmap.costs == 0).all()


def test_incremental_updates_equal_full_reinflation() -> None:
    grid, spec = pillar_world()
    params = CostmapParams()
    rng = np.random.default_rng(3)
    obstacle = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [StaticLayer(params), obstacle, InflationLayer()])
    costmap.set_map(grid, spec)
    first = costmap.update((-2.0, -0.5, 0.0))
    assert (first.x1 - first.x0, first.y1 - first.y0) == (spec.width, spec.height)
    world = grid.copy()
    world[(np.arange(spec.height)[:, None] % 17 == 0) & (np.arange(spec.width)[None, :] % 13 == 0)] = 100
    poses = [(-2.0, -0.5, 0.0), (-1.6, -0.3, 0.4), (-0.5, 0.5, 1.2), (0.6, -0.6, -2.0)]
    for pose in poses:
        obstacle.add_scan(
            fake_scan(world, spec, pose, beams=90, range_max=1.5, noise_std=0.02, rng=rng), pose
        )
        window = costmap.update(pose)
        assert 0 < (window.x1 - window.x0) * (window.y1 - window.y0) < spec.width * spec.height
    fresh_obstacle = ObstacleLayer(params)
    fresh = LayeredCostmap(params, [StaticLayer(params), fresh_obstacle, InflationLayer()])
    fresh.set_map(grid, spec)
    fresh_obstacle.grid[...] = obstacle.grid
    fresh.update(poses[-1])
    assert (obstacle.grid == 254).sum() > 0
    assert np.array_equal(costmap.costs, fresh.costs)


def test_clear_entirely_returns_to_the_static_map() -> None:
    grid, spec = pillar_world()
    params = CostmapParams()
    obstacle = ObstacleLayer(params)
    costmap = LayeredCostmap(params, [StaticLayer(params), obstacle, InflationLayer()])
    costmap.set_map(grid, spec)
    costmap.update((0.0, 0.0, 0.0))
    static_only = costmap.costs.copy()
    obstacle.add_scan(one_beam(0.6, angle=0.75), (-2.0, -2.0, 0.0))
    costmap.update((-2.0, -2.0, 0.0))
    assert not np.array_equal(costmap.costs, static_only)
    costmap.clear_entirely()
    costmap.update((-2.0, -2.0, 0.0))
    assert np.array_equal(costmap.costs, static_only)


def test_footprint_cost_sees_outline_interior_and_map_edge() -> None:
    spec = GridSpec(40, 40, 0.05)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    costs[20, 20] = 254  # cell centre (1.025, 1.025)
    fp = Footprint.from_polygon([[0.3, 0.3], [0.3, -0.3], [-0.3, -0.3], [-0.3, 0.3]])
    assert footprint_cost(costs, spec, fp, 1.0, 1.0, 0.3) == 254  # inside the robot
    assert footprint_cost(costs, spec, fp, 1.0, 1.0, 0.3, outline_only=True) == 0  # Nav2's outline check
    assert footprint_cost(costs, spec, fp, 1.3, 1.0, 0.0) == 254  # on the edge
    assert footprint_cost(costs, spec, fp, 0.5, 1.5, 0.0) == 0
    assert footprint_cost(costs, spec, fp, 0.1, 1.0, 0.0) == 254  # pokes off the grid
    poses = np.array([[1.0, 1.0, 0.3], [0.5, 1.5, 0.0], [0.1, 1.0, 0.0], [1.6, 1.0, 0.0]])
    singles = [footprint_cost(costs, spec, fp, *p) for p in poses]
    assert footprint_costs(costs, spec, fp, poses).tolist() == singles == [254, 0, 254, 0]


def test_squared_distance_transform_is_exact_within_cap() -> None:
    mask = np.random.default_rng(0).random((37, 53)) < 0.02
    got = squared_distance_cells(mask, 9)
    ys, xs = np.nonzero(mask)
    gy, gx = np.mgrid[0:37, 0:53]
    brute = ((gy[..., None] - ys) ** 2 + (gx[..., None] - xs) ** 2).min(axis=-1)
    assert np.array_equal(np.minimum(brute, 82), got)


def test_bad_configuration_is_rejected_with_the_field_name() -> None:
    with pytest.raises(ValueError, match="resolution"):
        CostmapParams(resolution=0.0)
    with pytest.raises(ValueError, match="robot_radius"):
        CostmapParams(robot_radius=-0.1)
    with pytest.raises(ValueError, match="combination_method"):
        ObstacleLayerParams(combination_method=5)
    with pytest.raises(ValueError, match="inflation_radius"):
        InflationLayerParams(inflation_radius=float("nan"))
    with pytest.raises(ValueError, match="rolling"):
        StaticLayer(CostmapParams.local_defaults())
    with pytest.raises(ValueError, match="finite"):
        LayeredCostmap(CostmapParams.local_defaults(), []).update((math.nan, 0.0, 0.0))
