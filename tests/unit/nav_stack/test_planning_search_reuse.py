"""Searches that share one SearchArrays (as a planner's do) each give the reference's result; build_path's
vectorised subdivision gives the poses of the per-segment construction it replaced."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from nav_stack.core.geometry import Pose2D, headings_along
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning import NavfnParams, NavfnPlanner, PlanningError, grid_search, grid_search_jit
from nav_stack.core.planning.common import build_path
from nav_stack.core.planning.grid_search import SearchGraph, SearchResult, navfn_cost_table
from tests.unit.nav_stack.test_grid_search_jit import _free_cell, _random_costmap


def _outcome(result: SearchResult, graph: SearchGraph) -> tuple[object, ...]:
    """All a search result says, comparable with ==: goal, expansions, expanded cells, every g and parent
    link (hence the path; a stale link could make ``cells_to`` loop, so the links are compared instead)."""
    assert len(result.g) == len(graph.codes)
    return (result.reached, result.expansions, result.expanded.tobytes(), result.g.tobytes(),
            result.parent.tobytes())


@pytest.mark.parametrize("use_astar", [True, False])
def test_searches_sharing_their_arrays_match_the_reference_on_every_search(use_astar: bool) -> None:
    """Searches on one SearchArrays, across maps of two sizes and back, each equal the reference's."""
    rng = np.random.default_rng(7)
    arrays = grid_search_jit.SearchArrays()
    for width, height in ((60, 40), (60, 40), (35, 70), (60, 40)):
        graph = SearchGraph.build(_random_costmap(rng, width, height), navfn_cost_table(allow_unknown=True))
        for _ in range(3):
            start = graph.index(*_free_cell(rng, graph, width, height))
            goal = graph.index(*_free_cell(rng, graph, width, height))
            args = (graph, start, goal, use_astar, 10**7, lambda: False)
            reference = _outcome(grid_search.search(*args), graph)
            assert _outcome(grid_search_jit.search(*args, arrays=arrays), graph) == reference


def test_a_search_after_a_timeout_starts_clean() -> None:
    """A search cut short by the iteration cap leaves nothing behind for the next one."""
    graph = SearchGraph.build(np.zeros((80, 80), dtype=np.uint8), navfn_cost_table(allow_unknown=False))
    arrays = grid_search_jit.SearchArrays()
    with pytest.raises(grid_search.SearchTimeoutError):
        grid_search_jit.search(graph, graph.index(0, 0), graph.index(79, 79), False, 500, lambda: False,
                               arrays)
    args = (graph, graph.index(79, 0), graph.index(0, 79), False, 10**7, lambda: False)
    reference = _outcome(grid_search.search(*args), graph)
    assert _outcome(grid_search_jit.search(*args, arrays=arrays), graph) == reference


def test_the_compiled_planner_plans_what_the_reference_planner_plans() -> None:
    """NavfnPlanner with its kept Searcher, plan after plan, equals the planner on the reference search."""
    rng = np.random.default_rng(3)
    costs = _random_costmap(rng, 70, 50)
    spec = GridSpec(70, 50, 0.05)
    compiled = NavfnPlanner(NavfnParams())
    reference = NavfnPlanner(NavfnParams(), search=grid_search.search)
    free = np.argwhere(costs < 128)
    for _ in range(8):
        (ay, ax), (by, bx) = free[rng.integers(len(free), size=2)]
        start = Pose2D(float(ax) * 0.05 + 0.025, float(ay) * 0.05 + 0.025, 0.0)
        goal = Pose2D(float(bx) * 0.05 + 0.025, float(by) * 0.05 + 0.025, 1.0)
        try:
            expected = reference.create_plan(start, goal, costs, spec)
        except PlanningError as exc:  # the same failure
            with pytest.raises(PlanningError) as failed:
                compiled.create_plan(start, goal, costs, spec)
            assert failed.value.code == exc.code
            continue
        np.testing.assert_array_equal(compiled.create_plan(start, goal, costs, spec), expected)


def _build_path_per_segment(points: np.ndarray, goal_yaw: float, spacing: float) -> np.ndarray:
    """build_path as it was written before it was vectorised: one segment at a time."""
    if len(points) == 1:
        return np.array([[points[0, 0], points[0, 1], goal_yaw]])
    pieces = []
    for a, b in itertools.pairwise(points):
        n = max(1, math.ceil(float(np.hypot(*(b - a))) / spacing - 0.5))
        pieces.append(a + np.arange(n)[:, None] / n * (b - a))
    pieces.append(points[-1:])
    xy = np.vstack(pieces)
    path = np.column_stack((xy, headings_along(xy)))
    path[-1, 2] = goal_yaw
    return path


@pytest.mark.parametrize("seed", range(6))
def test_build_path_subdivides_as_one_segment_at_a_time(seed: int) -> None:
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(int(rng.integers(1, 30)), 2)) * [0.05, 1.0, 4.0][seed % 3]
    if len(points) > 2:
        points[2] = points[1]  # a zero-length segment
    np.testing.assert_array_equal(build_path(points, 0.7, 0.05), _build_path_per_segment(points, 0.7, 0.05))
