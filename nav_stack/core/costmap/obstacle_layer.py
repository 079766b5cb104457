"""ObstacleLayer: marks laser returns as lethal and clears the space the beams crossed.

Semantics of nav2_costmap_2d::ObstacleLayer with one laser source: at each update all queued
scans first clear (ray tracing from the sensor up to ``raytrace_max_range``, skipping the first
``raytrace_min_range``, the return's own cell excluded), then mark returns whose distance lies in
``[obstacle_min_range, obstacle_max_range)``. Readings outside the scan's ``[range_min, range_max)``
or NaN are dropped; +inf clears up to ``range_max`` only when ``inf_is_valid``. With
``footprint_clearing_enabled`` the cells under the robot are set free. The layer keeps its own
grid (unknown until seen when ``track_unknown_space``) and merges it into the master by maximum
(``combination_method`` 1) or by overwriting with known cells (0).

The bounds it reports cover only the cells whose value its marking, clearing or footprint clearing
changed (Nav2 reports every cell a beam crossed): a robot among known surroundings then redraws,
inflates and publishes almost nothing, which is what keeps a warehouse-sized global costmap cheap
(issue 44). Clearing walks the beams in a compiled loop (raytrace_jit); marking is one numpy pass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nav_stack.core.costmap.footprint import Footprint
from nav_stack.core.costmap.layer import CostArray, Layer, Window, shifted
from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.costmap.params import CostmapParams, ObstacleLayerParams
from nav_stack.core.costmap.raytrace import ClearRays
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import FREE_SPACE, LETHAL_OBSTACLE, NO_INFORMATION, GridSpec


def _net_change(before: CostArray, after: CostArray, touched: Window) -> Window:
    """The smallest window of the cells inside ``touched`` whose value differs between the grids.

    Why not ``touched`` itself: a scan's clearing frees cells that its own marking then marks again
    (a beam passing through its neighbour's return), so a scan repeating the last one touches a ring
    of cells and changes none.
    """
    if touched.is_empty:
        return touched
    rows, cols = np.nonzero(before[touched.slices] != after[touched.slices])
    return Window.around(cols + touched.x0, rows + touched.y0)


@dataclass(frozen=True)
class _Observation:
    scan: LaserScan
    sensor_pose: Pose2D


class ObstacleLayer(Layer):
    """Keeps a grid of seen obstacles and free space, fed by laser scans."""

    def __init__(self, costmap_params: CostmapParams, params: ObstacleLayerParams | None = None,
                 name: str = "obstacle_layer", clear_rays: ClearRays | None = None) -> None:
        """``clear_rays``: None for the compiled clearing (raytrace_jit), or raytrace.clear_rays, the
        numpy reference, which gives the same grid (tests/unit/nav_stack/test_costmap_jit.py).

        numba is imported here, not with the package: AMCL and SLAM import the package for LaserScan.
        """
        if clear_rays is None:
            from nav_stack.core.costmap import raytrace_jit

            raytrace_jit.warm_up()  # compile or load it now (configure), not in the first scan's update
            clear_rays = raytrace_jit.clear_rays
        self._clear_rays = clear_rays
        self.name = name
        self.params = params or ObstacleLayerParams()
        self.enabled = self.params.enabled
        self._default = NO_INFORMATION if costmap_params.track_unknown_space else FREE_SPACE
        self._spec: GridSpec | None = None
        self._grid: CostArray | None = None
        self._queue: list[_Observation] = []
        self._footprint: Footprint | None = None

    @property
    def grid(self) -> CostArray:
        """The layer's own costs (LETHAL, FREE or its default per cell)."""
        if self._grid is None:
            raise RuntimeError(f"{self.name}: the costmap has no grid yet")
        return self._grid

    def add_scan(self, scan: LaserScan, sensor_pose: Pose2D) -> None:
        """Queue a scan taken from ``sensor_pose`` (x, y, yaw in the costmap's frame) for the next update."""
        self._queue.append(_Observation(scan, sensor_pose))

    def on_resize(self, spec: GridSpec) -> None:
        self._spec = spec
        self._grid = np.full(spec.shape, self._default, dtype=np.uint8)

    def on_shift(self, spec: GridSpec, dx: int, dy: int) -> None:
        self._spec = spec
        self._grid = shifted(self.grid, dx, dy, self._default)

    def on_footprint(self, footprint: Footprint) -> None:
        self._footprint = footprint

    def _beams(self, obs: _Observation) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Ranges, frame angles and a 'is a real return' flag of the usable beams of one scan."""
        scan, p = obs.scan, self.params
        ranges = np.asarray(scan.ranges, dtype=np.float64)
        angles = scan.angles + obs.sensor_pose[2]
        finite = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges < scan.range_max)
        use = finite | (np.isposinf(ranges) & p.inf_is_valid)
        lengths = np.where(finite, ranges, scan.range_max)[use]
        return lengths, angles[use], finite[use]

    def _process(self) -> Window:
        spec, grid, p = self._spec, self.grid, self.params
        assert spec is not None
        changed = Window.empty()
        beams = [(obs, *self._beams(obs)) for obs in self._queue]
        if p.clearing:
            for obs, lengths, angles, _ in beams:
                origin = (obs.sensor_pose[0], obs.sensor_pose[1])
                reach = np.minimum(lengths, p.raytrace_max_range)
                freed = self._clear_rays(grid, spec, origin, reach, angles, p.raytrace_min_range, FREE_SPACE)
                changed = changed.union(freed)
        if p.marking:
            for obs, lengths, angles, real in beams:
                mark = real & (lengths < p.obstacle_max_range) & (lengths >= p.obstacle_min_range)
                wx = obs.sensor_pose[0] + lengths[mark] * np.cos(angles[mark])
                wy = obs.sensor_pose[1] + lengths[mark] * np.sin(angles[mark])
                mx, my = spec.world_to_cell(wx, wy)
                inside = spec.in_bounds(mx, my)
                mx, my = mx[inside], my[inside]
                new = grid[my, mx] != LETHAL_OBSTACLE
                grid[my, mx] = LETHAL_OBSTACLE
                changed = changed.union(Window.around(mx[new], my[new]))
        self._queue.clear()
        return changed

    def update_bounds(self, robot_pose: Pose2D, bounds: Window) -> Window:
        if self._spec is None or not self.enabled:
            self._queue.clear()
            return bounds
        before = self.grid.copy()  # 1.7 MB for a warehouse map at 3 cm: well under a millisecond
        touched = self._process()
        if self.params.footprint_clearing_enabled and self._footprint is not None:
            my, mx = self._footprint.cells_at(self._spec, *robot_pose)
            new = self.grid[my, mx] != FREE_SPACE
            self.grid[my, mx] = FREE_SPACE
            touched = touched.union(Window.around(mx[new], my[new]))
        return bounds.union(_net_change(before, self.grid, touched.clipped(self._spec)))

    def update_costs(self, master: CostArray, window: Window) -> None:
        if self._grid is None or not self.enabled:
            return
        rows, cols = window.slices
        layer = self._grid[rows, cols]
        region = master[rows, cols]
        known = layer != NO_INFORMATION
        if self.params.combination_method == 1:
            known &= (region == NO_INFORMATION) | (region < layer)
        region[known] = layer[known]

    def reset(self) -> None:
        self._queue.clear()
        if self._grid is not None:
            self._grid.fill(self._default)
