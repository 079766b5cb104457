"""The costmap publication rules (Nav2's Costmap2DPublisher): full grid or redrawn window, table lookup."""

from __future__ import annotations

import numpy as np
import pytest

from nav_stack.core.costmap import (
    CostmapParams,
    InflationLayer,
    LayeredCostmap,
    ObstacleLayer,
    StaticLayer,
    inflation_layer,
    raytrace,
)
from nav_stack.core.costmap.layer import Window
from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.costmap.publish import COST_TRANSLATION_TABLE, PublishTracker, apply_update, occupancy_of
from nav_stack.core.grid import GridSpec

SPEC = GridSpec(40, 30, 0.05)
BIG = GridSpec(200, 150, 0.05)  # 10 m x 7.5 m: a scan and its inflation redraw a part of it
POSE = (5.0, 3.75, 0.0)


def test_translation_table_is_nav2s() -> None:
    table = COST_TRANSLATION_TABLE.astype(int)
    assert (table[0], table[253], table[254], table[255]) == (0, 99, 100, -1)
    assert [table[c] for c in (1, 128, 252)] == [1 + 97 * (c - 1) // 251 for c in (1, 128, 252)]
    assert table[1:253].min() == 1 and table[1:253].max() == 98
    costs = np.random.default_rng(0).integers(0, 256, (7, 9), dtype=np.uint8)
    assert np.array_equal(occupancy_of(costs), table[costs].astype(np.int8))


def test_first_publication_is_full_then_updates_of_the_redrawn_window_only() -> None:
    tracker = PublishTracker()
    assert tracker.next(SPEC).kind == "full"
    assert tracker.next(SPEC).kind == "none"
    tracker.add(Window(2, 3, 5, 6))
    tracker.add(Window(10, 1, 12, 4))
    plan = tracker.next(SPEC)
    assert (plan.kind, plan.window) == ("update", Window(2, 1, 12, 6))
    assert tracker.next(SPEC).kind == "none"


def test_resize_move_or_force_sends_the_full_grid_again() -> None:
    tracker = PublishTracker()
    tracker.next(SPEC)
    tracker.add(Window(0, 0, 3, 3))
    moved = GridSpec(40, 30, 0.05, origin_x=0.05)
    assert tracker.next(moved).kind == "full"
    assert tracker.next(moved).kind == "none"  # the full grid held the pending window
    assert tracker.next(moved, force_full=True).kind == "full"
    tracker.invalidate()
    assert tracker.next(moved).kind == "full"


def test_a_subscriber_applying_updates_keeps_the_published_grid() -> None:
    """Full grid then updates reproduce the master grid cell for cell through a real costmap."""
    params = CostmapParams(track_unknown_space=True)
    obstacle = ObstacleLayer(params, clear_rays=raytrace.clear_rays)
    inflation = InflationLayer(inflate=inflation_layer.inflate)
    costmap = LayeredCostmap(params, [StaticLayer(params), obstacle, inflation])
    occupancy = np.zeros(BIG.shape, dtype=np.int8)
    occupancy[:, 0] = 100
    costmap.set_map(occupancy, BIG)
    tracker = PublishTracker()
    tracker.add(costmap.update(POSE))
    assert tracker.next(BIG).kind == "full"
    seen = occupancy_of(costmap.costs)
    for ranges in (np.full(8, 0.5), np.full(8, 0.8)):  # the second clears the first one's returns
        obstacle.add_scan(LaserScan(ranges, 0.0, np.pi / 4, 0.1, 1.0), POSE)
        tracker.add(costmap.update(POSE))
        plan = tracker.next(BIG)
        assert plan.kind == "update" and plan.window.x0 > 0 and plan.window.x1 < BIG.width
        w = plan.window
        cells = occupancy_of(costmap.costs[w.slices]).ravel()
        apply_update(seen, w.x0, w.y0, w.x1 - w.x0, w.y1 - w.y0, cells)
        assert np.array_equal(seen, occupancy_of(costmap.costs))


def test_apply_update_rejects_a_window_off_the_grid() -> None:
    grid = np.zeros((4, 5), dtype=np.int8)
    apply_update(grid, 3, 2, 2, 2, [1, 2, 3, 4])
    assert grid[2:4, 3:5].tolist() == [[1, 2], [3, 4]]
    with pytest.raises(ValueError, match="outside"):
        apply_update(grid, 4, 0, 2, 1, [1, 2])
    with pytest.raises(ValueError, match="carries"):
        apply_update(grid, 0, 0, 2, 2, [1, 2, 3])
