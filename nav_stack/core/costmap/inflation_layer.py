"""InflationLayer: costs that fall off with distance from lethal cells (nav2 InflationLayer).

For a cell at distance d (m, cell centre to cell centre) from the nearest LETHAL cell of the
master grid: d = 0 → 254; d ≤ inscribed radius → 253; else ⌊252·exp(−cost_scaling_factor·(d − r_in))⌋,
for cells up to ``ceil(inflation_radius / resolution)`` cells away (Nav2's cell radius). A cell
keeps the larger of its own and the inflated cost; an unknown cell (255) takes the inflated cost only
when it is ≥ 253 (or > 0 with ``inflate_unknown``).

Distances come from the bounded exact transform in :mod:`distance`, as squared cell counts, so a
lookup table indexed by d² turns them into costs without a square root. Updates are incremental:
the layer grows the update window by the inflation radius, and inflates it from the lethal cells
of the window grown by the radius once more, which is exactly the set of cells that can change.

:func:`inflate` is the numpy reference of one update; the layer runs its compiled twin
(inflation_jit.inflate: the same costs, 14 ms of CPU instead of 150 ms for a whole 2000 x 2000 map)
unless given the reference.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.distance import squared_distance_cells
from nav_stack.core.costmap.footprint import Footprint
from nav_stack.core.costmap.layer import CostArray, Layer, Window
from nav_stack.core.costmap.params import InflationLayerParams
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
    GridSpec,
)


def inflation_cost(
    distance_m: npt.ArrayLike, inscribed_radius: float, cost_scaling_factor: float
) -> CostArray:
    """Nav2's computeCost for distances (m) from the nearest lethal cell (no radius cut-off)."""
    d = np.asarray(distance_m, dtype=np.float64)
    decayed = np.floor(MAX_NON_OBSTACLE * np.exp(-cost_scaling_factor * (d - inscribed_radius)))
    cost = np.where(d <= inscribed_radius, INSCRIBED_INFLATED_OBSTACLE, np.minimum(decayed, MAX_NON_OBSTACLE))
    return np.where(d == 0.0, LETHAL_OBSTACLE, cost).astype(np.uint8)


#: (master, window, region, cost table by d², radius in cells, lowest cost an unknown cell takes)
Inflate = Callable[[CostArray, Window, Window, CostArray, int, int], None]


def inflate(master: CostArray, window: Window, region: Window, table: CostArray, radius: int,
            threshold: int) -> None:
    """Inflate ``master`` inside ``window`` from the lethal cells inside ``region`` (numpy reference).

    ``region`` is ``window`` grown by ``radius`` cells and clipped to the grid: every lethal cell
    within ``radius`` of the window. ``table[d²]`` is the cost at squared distance d² (cells²),
    ``radius``² + 1 standing for "farther". A known cell keeps the larger of its cost and the
    inflated one; an unknown cell takes the inflated cost only when it is >= ``threshold``.
    """
    d2 = squared_distance_cells(master[region.slices] == LETHAL_OBSTACLE, radius)
    oy, ox = window.y0 - region.y0, window.x0 - region.x0
    cost = table[d2[oy : oy + window.y1 - window.y0, ox : ox + window.x1 - window.x0]]
    old = master[window.slices]
    unknown = old == NO_INFORMATION
    merged = np.maximum(old, cost)
    merged[unknown] = np.where(cost[unknown] >= threshold, cost[unknown], NO_INFORMATION)
    old[...] = merged


def cell_inflation_radius(inflation_radius: float, resolution: float) -> int:
    """Inflation radius in cells, rounded up like Costmap2D::cellDistance."""
    return max(0, math.ceil(inflation_radius / resolution - 1e-9))


class InflationLayer(Layer):
    """Inflates the master grid's lethal cells by the robot's inscribed radius and a decay."""

    def __init__(self, params: InflationLayerParams | None = None, name: str = "inflation_layer",
                 inflate: Inflate | None = None) -> None:
        """``inflate``: None for the compiled update (inflation_jit), or this module's reference
        :func:`inflate`, which gives the same costs (tests/unit/nav_stack/test_costmap_jit.py).

        numba is imported here, not with the package: AMCL and SLAM import the package for LaserScan.
        """
        if inflate is None:
            from nav_stack.core.costmap import inflation_jit

            inflation_jit.warm_up()  # compile or load it now (configure), not in the first map's update
            inflate = inflation_jit.inflate
        self._inflate = inflate
        self.name = name
        self.params = params or InflationLayerParams()
        self.enabled = self.params.enabled
        self._inscribed = 0.0
        self._spec: GridSpec | None = None
        self._radius_cells = 0
        self._table: CostArray = np.zeros(1, dtype=np.uint8)
        self._need_full = True

    @property
    def inscribed_radius(self) -> float:
        return self._inscribed

    @property
    def radius_cells(self) -> int:
        return self._radius_cells

    def _rebuild_table(self) -> None:
        if self._spec is None:
            return
        r = cell_inflation_radius(self.params.inflation_radius, self._spec.resolution)
        self._radius_cells = r
        d2 = np.arange(r * r + 2, dtype=np.float64)
        table = inflation_cost(np.sqrt(d2) * self._spec.resolution, self._inscribed,
                               self.params.cost_scaling_factor)
        table[d2 > r * r] = 0
        self._table = table
        self._need_full = True

    def on_resize(self, spec: GridSpec) -> None:
        self._spec = spec
        self._rebuild_table()

    def on_shift(self, spec: GridSpec, dx: int, dy: int) -> None:
        self._spec = spec
        self._need_full = True

    def on_footprint(self, footprint: Footprint) -> None:
        self._inscribed = footprint.inscribed_radius
        self._rebuild_table()

    def update_bounds(self, robot_pose: Pose2D, bounds: Window) -> Window:
        if self._spec is None or not self.enabled:
            return bounds
        if self._need_full:
            self._need_full = False
            return Window.full(self._spec)
        return bounds.expanded(self._radius_cells)

    def update_costs(self, master: CostArray, window: Window) -> None:
        if self._spec is None or not self.enabled or window.is_empty:
            return
        region = window.expanded(self._radius_cells).clipped(self._spec)
        threshold = 1 if self.params.inflate_unknown else INSCRIBED_INFLATED_OBSTACLE
        self._inflate(master, window, region, self._table, self._radius_cells, threshold)

    def reset(self) -> None:
        self._need_full = True
