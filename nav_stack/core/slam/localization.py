"""Localization on a saved pose graph: slam_toolbox's ``mode: localization``, in numpy.

Why a mode of the SLAM rather than AMCL: a saved graph holds the exact scans of the session, not
only the rendered map, so the robot is matched against the same evidence that built the map
(sharper than a likelihood field of the pgm), and a session can be mapped once, then localized
in for as long as the place does not change.

What it does per processed scan (one per ``minimum_travel_distance`` / ``minimum_travel_heading``
of odometry, as in mapping):

1. predict the pose as ``map_to_odom ∘ odom`` (the first scan: at the pose given to
   ``restart_at``, e.g. ``map_start_pose`` or DeserializePoseGraph's ``initial_pose``);
2. match the scan with the correlative matcher (the running-buffer window) against the saved
   map's occupied cells within laser range and the last ``scan_buffer_size`` localization scans,
   refining on the exact returns of the saved scans within ``loop_search_maximum_distance``;
3. publish ``map_to_odom = pose ∘ odom⁻¹``; keep the scan in the rolling buffer.

No node, edge or map cell is ever added: like slam_toolbox's localization mode (which drops its
localization scans from a rolling buffer), the saved graph and /map stay exactly as loaded.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import IDENTITY, FloatArray, Pose2D, compose
from nav_stack.core.slam.correlation import MatchResult
from nav_stack.core.slam.laser import ScanPoints, joined_returns, scan_points, to_map
from nav_stack.core.slam.mapper import GridSlam
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.serialization import SlamGraph
from nav_stack.core.slam.shared import SlamUpdate, check_inputs, due, inverse, match_scan

# A match weaker than this (mean smear, 0..1) keeps the odometry prediction (as in mapping).
_MIN_RESPONSE = 0.1
# At most this many saved scans near the robot are refined against (bounds the cost per scan).
_NEAR_NODES = 30


class GraphLocalizer(GridSlam):
    """Tracks the robot on a restored graph; build it with ``GraphLocalizer.from_graph``."""

    def __init__(self, params: SlamParams | None = None) -> None:
        super().__init__(params)
        # (hits, joined hits) of recent localization scans in the map frame; never part of the graph
        self._recent: deque[tuple[FloatArray, FloatArray]] = deque(maxlen=self.params.scan_buffer_size)
        self._last_odom: Pose2D | None = None
        self.localized_scans = 0  # processed scans whose match was accepted

    def restart_at(self, pose: Pose2D) -> None:
        """Localize from ``pose`` (map frame) on the next scan; forget the rolling buffer."""
        super().restart_at(pose)
        self._recent.clear()
        self._last_odom = None

    def process(
        self, scan: LaserScan, odom_pose: Pose2D, stamp: float, laser_pose: Pose2D = IDENTITY
    ) -> SlamUpdate:
        """Feed one scan with the odometry pose (odom frame) at its ``stamp`` (s); see the module
        docstring. The graph and the map are left unchanged."""
        check_inputs(odom_pose, laser_pose, stamp)
        if not len(self._poses):
            raise ValueError("GraphLocalizer.process: no saved graph loaded (use GraphLocalizer.from_graph)")
        p = self.params
        if self._restart is not None or self._last_odom is None:
            predicted = self._restart or compose(self._map_to_odom, odom_pose)
        else:
            predicted = compose(self._map_to_odom, odom_pose)
            if not due(p, self._last_odom, odom_pose, stamp - self._stamp):
                return SlamUpdate(self._map_to_odom, predicted, processed=False)
        points = scan_points(scan, laser_pose, p.max_laser_range)
        result = self._match_saved(points, predicted)
        pose, response = predicted, 0.0
        if result is not None and result.response >= _MIN_RESPONSE:
            pose, response = result.pose, result.response
            self.localized_scans += 1
        self._restart, self._last_odom, self._stamp = None, odom_pose, stamp
        self._map_to_odom = compose(pose, inverse(odom_pose))
        joined = joined_returns(points.hits, p.refine_resolution)
        self._recent.append((to_map(points.hits, pose), to_map(joined, pose)))
        return SlamUpdate(self._map_to_odom, pose, processed=True, response=response)

    def _match_saved(self, points: ScanPoints, predicted: Pose2D) -> MatchResult | None:
        """Match against the saved map near ``predicted`` plus the rolling buffer; refine on the
        exact returns of the nearest saved scans."""
        p = self.params
        half = p.max_laser_range + self._link_window.half_extent
        near_map = self._grid.occupied_points((predicted.x, predicted.y), half, p.occupied_thresh)
        d = np.hypot(self._poses[:, 0] - predicted.x, self._poses[:, 1] - predicted.y)
        close = np.argsort(d)[:_NEAR_NODES]
        close = close[d[close] <= p.loop_search_maximum_distance]
        reference = np.vstack([near_map, *(hits for hits, _ in self._recent)])
        fine = np.vstack([self._dense_hits_in_map(sorted(close.tolist())), *(j for _, j in self._recent)])
        return match_scan(p, reference, points.hits, predicted, self._link_window, fine)


def resume(graph: SlamGraph, params: SlamParams, start: Pose2D | None, localize: bool) -> GridSlam:
    """A session continued from a saved ``graph`` (mapping) or localizing on it (``localize``), the
    robot at ``start`` (map frame; None: the graph's first node, slam_toolbox's "dock") on the next
    scan. Raises ValueError for an empty graph or a resolution other than the saved one."""
    if not len(graph.poses):
        raise ValueError("the saved graph has no nodes")
    slam = (GraphLocalizer if localize else GridSlam).from_graph(graph, params)
    slam.restart_at(Pose2D(*map(float, graph.poses[0])) if start is None else start)
    return slam
