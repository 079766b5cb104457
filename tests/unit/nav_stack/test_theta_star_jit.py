"""The compiled Theta* gives the reference's chains, errors and limits."""

from __future__ import annotations

import numpy as np
import pytest

from nav_stack.core.planning import theta_star, theta_star_jit
from nav_stack.core.planning.errors import PlanErrorCode, PlanningError
from nav_stack.core.planning.grid_search import SearchGraph
from nav_stack.core.planning.theta_star import ThetaStarParams, theta_cost_table
from tests.unit.nav_stack.test_grid_search_jit import _free_cell, _random_costmap


def _outcome(search, *args) -> tuple[str, object]:  # type: ignore[no-untyped-def]
    try:
        return "chain", search(*args)
    except PlanningError as error:
        return "error", (error.code, str(error))


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("corners", [4, 8])
def test_same_chain_as_the_reference(seed: int, corners: int) -> None:
    rng = np.random.default_rng(100 + seed)
    width, height = int(rng.integers(20, 70)), int(rng.integers(20, 70))
    table = theta_cost_table(allow_unknown=seed % 2 == 0)
    graph = SearchGraph.build(_random_costmap(rng, width, height), table)
    start = graph.index(*_free_cell(rng, graph, width, height))
    goal = graph.index(*_free_cell(rng, graph, width, height))
    params = ThetaStarParams(how_many_corners=corners, w_traversal_cost=float(seed % 3))
    args = (graph, start, goal, params, lambda: False)
    assert _outcome(theta_star_jit.search, *args) == _outcome(theta_star.search, *args)


def test_a_walled_off_goal_and_the_limits_raise_as_in_the_reference() -> None:
    codes = np.zeros((40, 40), dtype=np.uint8)
    codes[:, 20] = 254
    graph = SearchGraph.build(codes, theta_cost_table(allow_unknown=False))
    start, goal = graph.index(0, 0), graph.index(39, 39)
    capped = ThetaStarParams(max_iterations=50)
    for search in (theta_star.search, theta_star_jit.search):
        with pytest.raises(PlanningError) as walled:
            search(graph, start, goal, ThetaStarParams(), lambda: False)
        assert walled.value.code is PlanErrorCode.NO_VALID_PATH
        with pytest.raises(PlanningError, match="iteration cap of 50"):
            search(graph, start, goal, capped, lambda: False)
        with pytest.raises(PlanningError, match="max_planning_time"):
            search(graph, start, goal, ThetaStarParams(), lambda: True)
