"""StaticLayer: costs from the occupancy map (nav2_costmap_2d::StaticLayer semantics).

Map value -1 (read as 255 = ``unknown_cost_value``) → NO_INFORMATION if ``track_unknown_space``
else FREE_SPACE; value ≥ ``lethal_cost_threshold`` → LETHAL_OBSTACLE; other values → FREE_SPACE
when ``trinary_costmap``, else ``value / lethal_cost_threshold · 254`` (truncated). By default the
layer overwrites the master in its window, unknown included (``use_maximum`` false); with
``use_maximum`` known costs are max-combined.

A static layer needs a map-sized (non-rolling) costmap; the costmap sizes itself from the map.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.layer import CostArray, Layer, Window
from nav_stack.core.costmap.params import CostmapParams, StaticLayerParams
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION, GridSpec


def costs_from_occupancy(occupancy: npt.NDArray[np.int8], params: CostmapParams) -> CostArray:
    """Translate OccupancyGrid values (0..100, -1) to Nav2 costs as StaticLayer::interpretValue does."""
    value = occupancy.astype(np.int16) & 0xFF  # -1 → 255, as the uint8 message data is read
    if params.trinary_costmap:
        out = np.full(value.shape, FREE_SPACE, dtype=np.uint8)
    else:
        out = (value.astype(np.float64) / params.lethal_cost_threshold * LETHAL_OBSTACLE).astype(np.uint8)
    out[value >= params.lethal_cost_threshold] = LETHAL_OBSTACLE
    unknown = value == params.unknown_cost_value
    out[unknown] = NO_INFORMATION if params.track_unknown_space else FREE_SPACE
    return out


class StaticLayer(Layer):
    """Holds the map's costs and writes them into the master grid."""

    def __init__(self, costmap_params: CostmapParams, params: StaticLayerParams | None = None,
                 name: str = "static_layer") -> None:
        if costmap_params.rolling_window:
            raise ValueError(f"{name}: a static layer in a rolling-window costmap is not supported; "
                             "set rolling_window false or drop the static layer")
        self.name = name
        self.params = params or StaticLayerParams()
        self.enabled = self.params.enabled
        self._costmap_params = costmap_params
        self._costs: CostArray | None = None
        self._spec: GridSpec | None = None
        self._dirty = False

    @property
    def has_map(self) -> bool:
        return self._costs is not None

    def set_map(self, occupancy: npt.NDArray[np.int8], spec: GridSpec) -> None:
        """Take a new map (OccupancyGrid layout); the whole grid is redrawn at the next update."""
        if occupancy.shape != spec.shape:
            raise ValueError(f"{self.name}: map data shape {occupancy.shape} does not match {spec.shape}")
        self._costs = costs_from_occupancy(occupancy, self._costmap_params)
        self._spec = spec
        self._dirty = True

    def on_resize(self, spec: GridSpec) -> None:
        if self._spec is not None and self._spec.shape != spec.shape:
            raise ValueError(f"{self.name}: costmap grid {spec.shape} differs from map {self._spec.shape}")
        self._dirty = True

    def update_bounds(self, robot_pose: Pose2D, bounds: Window) -> Window:
        if self._spec is None or not self._dirty:
            return bounds
        self._dirty = False
        return bounds.union(Window.full(self._spec))

    def update_costs(self, master: CostArray, window: Window) -> None:
        if self._costs is None or not self.enabled:
            return
        rows, cols = window.slices
        layer = self._costs[rows, cols]
        if not self.params.use_maximum:
            master[rows, cols] = layer
            return
        region = master[rows, cols]
        known = layer != NO_INFORMATION
        take = known & ((region == NO_INFORMATION) | (region < layer))
        region[take] = layer[take]

    def reset(self) -> None:
        self._dirty = True
