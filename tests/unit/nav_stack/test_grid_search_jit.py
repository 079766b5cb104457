"""The compiled grid search gives the reference's result: the same paths, costs and expanded cells."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nav_stack.core.planning import grid_search, grid_search_jit
from nav_stack.core.planning.grid_search import SearchGraph, SearchTimeoutError, navfn_cost_table


def _random_costmap(rng: np.random.Generator, width: int, height: int) -> np.ndarray:
    """Lethal blocks, inscribed rims and graded costs around them, some unknown cells: a costmap's codes."""
    costs = rng.integers(0, 60, size=(height, width)).astype(np.uint8)
    for _ in range(width * height // 40):
        x, y = int(rng.integers(0, width)), int(rng.integers(0, height))
        rim = costs[max(0, y - 2):y + 3, max(0, x - 2):x + 3]
        rim[...] = np.maximum(rim, 200)
        costs[max(0, y - 1):y + 2, max(0, x - 1):x + 2] = 253
        costs[y, x] = 254
    costs[rng.random((height, width)) < 0.02] = 255
    return costs


def _free_cell(rng: np.random.Generator, graph: SearchGraph, width: int, height: int) -> tuple[int, int]:
    while True:
        cell = int(rng.integers(0, width)), int(rng.integers(0, height))
        if graph.passable(*cell):
            return cell


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("use_astar", [True, False])
def test_same_path_cost_and_expansions_as_the_reference(seed: int, use_astar: bool) -> None:
    rng = np.random.default_rng(seed)
    width, height = int(rng.integers(20, 90)), int(rng.integers(20, 90))
    table = navfn_cost_table(allow_unknown=seed % 2 == 0)
    graph = SearchGraph.build(_random_costmap(rng, width, height), table)
    start = graph.index(*_free_cell(rng, graph, width, height))
    goal = graph.index(*_free_cell(rng, graph, width, height))
    args = (graph, start, goal, use_astar, 10**7, lambda: False)
    reference, compiled = grid_search.search(*args), grid_search_jit.search(*args)

    assert compiled.reached == reference.reached
    assert compiled.expansions == reference.expansions
    np.testing.assert_array_equal(compiled.expanded, reference.expanded)
    np.testing.assert_array_equal(compiled.g, reference.g)
    if reference.reached is not None:
        assert compiled.cells_to(graph, goal) == reference.cells_to(graph, goal)
        assert math.isfinite(compiled.g[goal])


def test_the_iteration_cap_and_the_deadline_stop_it_as_they_stop_the_reference() -> None:
    graph = SearchGraph.build(np.zeros((200, 200), dtype=np.uint8), navfn_cost_table(allow_unknown=False))
    start, goal = graph.index(0, 0), graph.index(199, 199)
    for search in (grid_search.search, grid_search_jit.search):
        with pytest.raises(SearchTimeoutError, match="iteration cap of 500"):
            search(graph, start, goal, False, 500, lambda: False)
        with pytest.raises(SearchTimeoutError, match="deadline passed"):
            search(graph, start, goal, False, 10**7, lambda: True)
