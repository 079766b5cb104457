"""LayeredCostmap: the master cost grid, its layers, the rolling window and footprint checks.

Why: this is the pure heart of a costmap node (nav2 Costmap2DROS + LayeredCostmap). The node feeds
maps and scans to the layers, calls :meth:`update` at ``update_frequency`` with the robot pose in
the costmap frame, and publishes :attr:`costs` (or the returned window for partial updates).

Each update: a rolling window recentres on the robot (contents shift, uncovered cells reset);
layers report the window they changed; the master resets that window (NO_INFORMATION when
``track_unknown_space``, else FREE_SPACE) and the layers write into it in order (static overwrites,
obstacle max-combines, inflation inflates).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.footprint import Footprint
from nav_stack.core.costmap.layer import CostArray, Layer, Window, shifted
from nav_stack.core.costmap.params import CostmapParams
from nav_stack.core.costmap.static_layer import StaticLayer
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import FREE_SPACE, NO_INFORMATION, GridSpec


class LayeredCostmap:
    """A master uint8 cost grid kept up to date by an ordered list of layers."""

    def __init__(self, params: CostmapParams, layers: Sequence[Layer], spec: GridSpec | None = None) -> None:
        self.params = params
        self.layers = list(layers)
        self.default_value = NO_INFORMATION if params.track_unknown_space else FREE_SPACE
        self._footprint = Footprint.from_params(params)
        self._spec: GridSpec | None = None
        self._costs: CostArray = np.zeros((0, 0), dtype=np.uint8)
        self._pending = Window.empty()
        for layer in self.layers:
            layer.on_footprint(self._footprint)
        if spec is None and params.rolling_window:
            cells_x = max(1, round(params.width / params.resolution))
            cells_y = max(1, round(params.height / params.resolution))
            spec = GridSpec(cells_x, cells_y, params.resolution, params.origin_x, params.origin_y)
        if spec is not None:
            self.resize(spec)

    @property
    def spec(self) -> GridSpec:
        if self._spec is None:
            raise RuntimeError("costmap has no size yet: give it a spec or a map (set_map)")
        return self._spec

    @property
    def is_sized(self) -> bool:
        return self._spec is not None

    @property
    def costs(self) -> CostArray:
        """The master grid ``[my, mx]`` of Nav2 costs (0..255); row 0 is the bottom."""
        return self._costs

    @property
    def footprint(self) -> Footprint:
        return self._footprint

    @property
    def inscribed_radius(self) -> float:
        return self._footprint.inscribed_radius

    @property
    def circumscribed_radius(self) -> float:
        return self._footprint.circumscribed_radius


    def resize(self, spec: GridSpec) -> None:
        """(Re)allocate the master and every layer for ``spec``; everything is redrawn next update."""
        self._spec = spec
        self._costs = np.full(spec.shape, self.default_value, dtype=np.uint8)
        for layer in self.layers:
            layer.on_resize(spec)
        self._pending = Window.full(spec)

    def set_map(self, occupancy: npt.NDArray[np.int8], spec: GridSpec) -> None:
        """Hand a new occupancy map to the static layers; a static costmap takes the map's size."""
        static = [layer for layer in self.layers if isinstance(layer, StaticLayer)]
        if not static:
            raise ValueError("this costmap has no static layer to take a map")
        for layer in static:
            layer.set_map(occupancy, spec)
        if self._spec != spec:
            self.resize(spec)

    def _recentre(self, x: float, y: float) -> None:
        """Move a rolling window so the robot is at its centre (whole-cell shifts only)."""
        spec = self.spec
        target_x = x - spec.size_m[0] / 2.0
        target_y = y - spec.size_m[1] / 2.0
        dx = int((target_x - spec.origin_x) / spec.resolution)
        dy = int((target_y - spec.origin_y) / spec.resolution)
        if dx == 0 and dy == 0:
            return
        new_spec = GridSpec(spec.width, spec.height, spec.resolution, spec.origin_x + dx * spec.resolution,
                            spec.origin_y + dy * spec.resolution)
        self._spec = new_spec
        self._costs = shifted(self._costs, dx, dy, self.default_value)
        for layer in self.layers:
            layer.on_shift(new_spec, dx, dy)
        self._pending = Window.full(new_spec)

    def update(self, robot_pose: Pose2D) -> Window:
        """Run one cycle at ``robot_pose`` (x, y, yaw in the costmap frame); return the redrawn window."""
        if not all(math.isfinite(v) for v in robot_pose):
            raise ValueError(f"robot pose must be finite, got {robot_pose}")
        spec = self.spec
        if self.params.rolling_window:
            self._recentre(robot_pose[0], robot_pose[1])
            spec = self.spec
        bounds = self._pending
        self._pending = Window.empty()
        for layer in self.layers:
            bounds = layer.update_bounds(robot_pose, bounds)
        window = bounds.clipped(spec)
        if window.is_empty:
            return window
        self._costs[window.slices] = self.default_value
        for layer in self.layers:
            if layer.enabled:
                layer.update_costs(self._costs, window)
        return window

    def redraw_all(self) -> None:
        """Redraw the whole grid at the next update (a layer was switched on or off)."""
        if self._spec is not None:
            self._pending = Window.full(self._spec)

    def clear_entirely(self) -> None:
        """Reset every layer (obstacles forgotten, static map kept) and redraw all at the next update."""
        for layer in self.layers:
            layer.reset()
        if self._spec is not None:
            self._costs.fill(self.default_value)
            self._pending = Window.full(self._spec)

