"""The replan rule (nav_stack/core/planning/replan.py): a replan to the same goal keeps the rest of the
last plan only when no search could find a cheaper path, and its answer always costs the optimum."""

from __future__ import annotations

import numpy as np
import pytest

from nav_stack.core.grid import FREE_SPACE, LETHAL_OBSTACLE, GridSpec
from nav_stack.core.planning import NavfnParams, NavfnPlanner, PlanningError
from nav_stack.core.planning.grid_search import navfn_traversal_costs
from nav_stack.core.planning.replan import changed_cells, octile
from tests.unit.nav_stack.test_planning import (
    RES,
    brute_force_costs,
    cells_cost,
    centre,
    path_cells,
    random_costmap,
)


def _wall_with_a_closed_door(size: int = 20) -> np.ndarray:
    """Free space split by a wall at x = 10 with a gap at the top; the door at y = 4..6 closed."""
    costs = np.zeros((size, size), dtype=np.uint8)
    costs[: size - 3, 10] = LETHAL_OBSTACLE
    return costs


def _planner(use_astar: bool = True) -> NavfnPlanner:
    return NavfnPlanner(NavfnParams(use_astar=use_astar, tolerance=0.0))


def _replan_from_the_middle(planner: NavfnPlanner, costs: np.ndarray, new_costs: np.ndarray,
                            spec: GridSpec) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    goal = centre(spec, 18, 2, 0.3)
    first = path_cells(spec, planner.create_plan(centre(spec, 2, 2), goal, costs, spec))
    middle = first[len(first) // 4]
    again = planner.create_plan(centre(spec, *middle), goal, new_costs, spec)
    return first, path_cells(spec, again)


def test_an_unchanged_costmap_keeps_the_rest_of_the_plan() -> None:
    spec, costs = GridSpec(20, 20, RES), _wall_with_a_closed_door()
    planner = _planner()
    first, again = _replan_from_the_middle(planner, costs, costs.copy(), spec)
    assert planner.memory.kept == 1
    assert again == first[first.index(again[0]):]


def test_a_cost_rise_elsewhere_keeps_the_plan_and_one_on_it_does_not() -> None:
    spec, costs = GridSpec(20, 20, RES), _wall_with_a_closed_door()
    planner = _planner()
    elsewhere = costs.copy()
    elsewhere[0:2, 0:2] = 200  # dearer cells behind the start: no path gets cheaper
    _replan_from_the_middle(planner, costs, elsewhere, spec)
    assert planner.memory.kept == 1

    planner = _planner()
    first = path_cells(spec, planner.create_plan(centre(spec, 2, 2), centre(spec, 18, 2, 0.3), costs, spec))
    on_plan = costs.copy()
    x, y = first[len(first) // 2]
    on_plan[y, x] = LETHAL_OBSTACLE
    again = path_cells(spec, planner.create_plan(centre(spec, *first[1]), centre(spec, 18, 2, 0.3), on_plan,
                                                 spec))
    assert planner.memory.kept == 0, "a plan through a new obstacle was kept"
    assert (x, y) not in again


def test_an_opened_door_is_searched_and_taken() -> None:
    spec, costs = GridSpec(20, 20, RES), _wall_with_a_closed_door()
    planner = _planner()
    opened = costs.copy()
    opened[2:5, 10] = FREE_SPACE  # a shortcut next to the robot's way round the wall
    first, again = _replan_from_the_middle(planner, costs, opened, spec)
    assert planner.memory.kept == 0
    traversal = navfn_traversal_costs(opened, allow_unknown=True)
    assert cells_cost(traversal, again) < cells_cost(traversal, first[first.index(again[0]):])
    assert cells_cost(traversal, again) == pytest.approx(brute_force_costs(traversal, again[0])[2, 18])


def test_a_cheaper_cell_too_far_off_to_help_keeps_the_plan() -> None:
    spec, costs = GridSpec(40, 20, RES), np.full((20, 40), 100, dtype=np.uint8)
    costs[:, 20:] = 0
    costs[15:, 25:] = 50  # will drop to 0: far beyond any cheaper path from (2..) to (18, 2)
    planner = _planner()
    goal = centre(spec, 18, 2, 0.3)
    first = path_cells(spec, planner.create_plan(centre(spec, 2, 2), goal, costs, spec))
    cheaper = costs.copy()
    cheaper[15:, 25:] = 0
    again = path_cells(spec, planner.create_plan(centre(spec, *first[3]), goal, cheaper, spec))
    assert planner.memory.kept == 1
    assert again == first[3:]


def test_off_the_plan_another_goal_or_an_escape_is_searched() -> None:
    spec, costs = GridSpec(20, 20, RES), _wall_with_a_closed_door()
    planner = _planner()
    goal = centre(spec, 18, 2, 0.3)
    first = path_cells(spec, planner.create_plan(centre(spec, 2, 2), goal, costs, spec))
    off = next((x, y + 2) for x, y in first[3:] if (x, y + 2) not in first and costs[y + 2, x] == 0)
    planner.create_plan(centre(spec, *off), goal, costs, spec)
    planner.create_plan(centre(spec, *first[2]), centre(spec, 18, 3, 0.3), costs, spec)
    assert planner.memory.kept == 0
    inscribed = costs.copy()
    inscribed[first[2][1], first[2][0]] = 253  # the robot's cell in an inscribed band
    planner.create_plan(centre(spec, *first[2]), centre(spec, 18, 3, 0.3), inscribed, spec)
    assert planner.memory.kept == 0


@pytest.mark.parametrize("use_astar", [True, False])
def test_every_replan_costs_the_optimum_under_random_changes(use_astar: bool) -> None:
    """Random costmaps change between replans (rises, drops, new and removed obstacles) while the robot
    moves along its plan: each replan, kept or searched, costs what Bellman-Ford says is optimal."""
    rng = np.random.default_rng(11)
    spec = GridSpec(14, 14, RES)
    kept = 0
    for _ in range(12):
        costs = random_costmap(rng, 14, 0.15)
        free = np.argwhere(costs < 253)
        (sy, sx), (gy, gx) = free[rng.choice(len(free), 2, replace=False)]
        planner, goal = _planner(use_astar), centre(spec, gx, gy)
        start = (int(sx), int(sy))
        for _ in range(6):
            if start == (gx, gy):
                break
            try:
                cells = path_cells(spec, planner.create_plan(centre(spec, *start), goal, costs, spec))
            except PlanningError:
                break
            traversal = navfn_traversal_costs(costs, allow_unknown=True)
            optimum = brute_force_costs(traversal, start)[gy, gx]
            assert cells[0] == start and cells[-1] == (gx, gy)
            assert cells_cost(traversal, cells) == pytest.approx(optimum, rel=1e-5)
            start = cells[min(len(cells) - 1, int(rng.integers(1, 4)))]
            changes = rng.integers(0, 14, (int(rng.integers(0, 4)), 2))
            costs = costs.copy()
            for x, y in changes:
                if (x, y) not in (start, (gx, gy)):
                    costs[y, x] = rng.choice([0, 0, 30, 120, 200, LETHAL_OBSTACLE])
        kept += planner.memory.kept
    assert kept >= 5, "the rule never kept a plan: the test no longer covers it"


def test_octile_is_the_8_connected_walk_length() -> None:
    assert octile(0, 0, 3, 1) == pytest.approx(2 + 2**0.5)
    assert octile([0, 5], [0, 5], 5, 5).tolist() == pytest.approx([5 * 2**0.5, 0.0])


@pytest.mark.parametrize("shape", [(5, 8), (7, 9), (1, 3), (40, 41)])
def test_changed_cells_finds_every_changed_cell(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(shape[1])
    before = rng.integers(0, 256, shape).astype(np.uint8)
    after = before.copy()
    after[rng.random(shape) < 0.1] ^= 1
    after[-1, -1] ^= 7  # a cell in the last, partial word
    rows, cols = changed_cells(before, after)
    expected = np.nonzero(before != after)
    assert rows.tolist() == expected[0].tolist() and cols.tolist() == expected[1].tolist()
