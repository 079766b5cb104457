"""Grid SLAM (the role of slam_toolbox in the seed): correct odometry by scan matching, close loops
with a pose graph, and render a log-odds occupancy map in the map frame.

Per processed scan (one per ``minimum_travel_distance`` / ``minimum_travel_heading`` of motion):

1. predict the robot pose in the map as ``map_to_odom ∘ odom``;
2. match the scan against the running buffer (the last ``scan_buffer_size`` scans) and the map
   with the correlative matcher around the prediction, then refine the pose on a finer grid of
   the exact returns of the buffer and of the scans within ``refine_scan_distance``, joined into
   lines (tracking.py); a weak response keeps the prediction, and so does a direction the match
   leaves degenerate, but for the correction of the returns facing it (match_information.py);
3. add a pose-graph node with a sequential edge as certain as the match per direction, and fold
   the scan into the log-odds grid;
4. look for a loop closure against the nearest older, unlinked scan chain, within a window as wide
   as the graph's drift between the chain and the new scan (loop_closure.py); a match with strong
   responses and a distinct peak adds a robust edge weighted by the match covariance, the whole
   graph is re-optimised (Cauchy kernel on loop edges) and the map is re-rendered from the moved
   nodes, a slice per scan (rerender.py);
5. ``map_to_odom = pose ∘ odom⁻¹``, so the correction stays small and odom stays continuous.

Scans between processed ones only update the reported pose through the last correction.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import IDENTITY, FloatArray, Pose2D, compose
from nav_stack.core.grid import GridSpec
from nav_stack.core.slam import integrate_jit, pose_graph_jit
from nav_stack.core.slam.correlation import CorrelationGrid, MatchResult, SearchWindow
from nav_stack.core.slam.laser import ScanPoints, clouds_in_map, joined_returns, scan_points
from nav_stack.core.slam.log_odds import LogOddsGrid
from nav_stack.core.slam.loop_closure import search_loop
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.pose_graph import Edge, optimize
from nav_stack.core.slam.rerender import RERENDER_SLICE_NODES, Rerender
from nav_stack.core.slam.serialization import SlamGraph
from nav_stack.core.slam.shared import (
    SlamUpdate,
    between,
    check_inputs,
    due,
    inverse,
    loop_information,
)
from nav_stack.core.slam.tracking import match_running_buffer, prediction_stddev, track, trusted


class GridSlam:
    """Online 2D SLAM over LaserScans and odometry; see the module docstring for the pipeline."""

    def __init__(self, params: SlamParams | None = None) -> None:
        self.params = params or SlamParams()
        p = self.params
        integrate_jit.warm_up()  # load the compiled kernels now, not in the first scan's callback
        pose_graph_jit.warm_up()
        self._grid = self._new_grid()
        self._poses: FloatArray = np.zeros((0, 3))
        self._odom: list[Pose2D] = []
        self._raw: list[tuple[LaserScan, Pose2D]] = []  # each node's scan and laser pose, for saving
        self._restart: Pose2D | None = None  # where a restored session resumes (restart_at)
        self._scans: list[ScanPoints] = []
        self._dense: list[FloatArray] = []  # hits of each scan joined into lines (robot frame)
        self._adjacency: list[list[int]] = []
        self._edges: list[Edge] = []
        self._stamp = -math.inf
        self._map_to_odom = Pose2D(0.0, 0.0, 0.0)
        self._rerender: Rerender | None = None  # a re-render after a loop closure, in progress
        self.loop_closures = 0
        self.loop_closures_rejected = 0
        self._last_closure = -(10**9)
        s_xy, s_yaw = p.link_stddev_xy, p.link_stddev_yaw
        self._information = np.diag([1.0 / s_xy**2, 1.0 / s_xy**2, 1.0 / s_yaw**2])
        self._link_window = SearchWindow(
            half_extent=p.correlation_search_space_dimension / 2.0,
            half_angle=p.coarse_search_angle_offset,
            coarse_angle_resolution=p.coarse_angle_resolution,
            fine_angle_resolution=p.fine_search_angle_offset,
            distance_variance_penalty=p.distance_variance_penalty,
            angle_variance_penalty=p.angle_variance_penalty,
            minimum_distance_penalty=p.minimum_distance_penalty,
            minimum_angle_penalty=p.minimum_angle_penalty,
            refine_iterations=p.refine_iterations,
        )
        self._loop_window = replace(self._link_window, half_extent=p.loop_search_space_dimension / 2.0)

    @property
    def map_to_odom(self) -> Pose2D:
        """Current map → odom correction."""
        return self._map_to_odom

    @property
    def poses(self) -> FloatArray:
        """(N, 3) robot poses in the map of the processed scans (pose-graph nodes), oldest first."""
        return np.array(self._poses, dtype=np.float64, copy=True)

    @property
    def edges(self) -> tuple[Edge, ...]:
        """Pose-graph constraints, sequential and loop (``robust``), in the order they were added."""
        return tuple(self._edges)

    def process(
        self, scan: LaserScan, odom_pose: Pose2D, stamp: float, laser_pose: Pose2D = IDENTITY
    ) -> SlamUpdate:
        """Feed one scan with the odometry pose (odom frame) at its ``stamp`` (s).

        ``laser_pose`` is the sensor pose in the robot base frame (TF base_footprint → base_scan).
        Each call also advances a pending re-render of the map by one slice (rerender.py), so no
        call costs a whole re-render.
        """
        update = self._process(scan, odom_pose, stamp, laser_pose)
        self._advance_rerender(RERENDER_SLICE_NODES)
        return update

    def _new_grid(self) -> LogOddsGrid:
        p = self.params
        clamp = (p.clamp_min_probability, p.clamp_max_probability)
        return LogOddsGrid(p.resolution, p.hit_probability, p.miss_probability, clamp)

    def _advance_rerender(self, budget: int | None) -> None:
        """Fold ``budget`` more nodes (all if None) into the pending re-render; swap it in once complete."""
        if self._rerender is not None and self._rerender.advance(self._scans, self._poses, budget):
            self._grid, self._rerender = self._rerender.grid, None

    def _process(self, scan: LaserScan, odom_pose: Pose2D, stamp: float, laser_pose: Pose2D) -> SlamUpdate:
        check_inputs(odom_pose, laser_pose, stamp)
        if self._restart is not None and self._odom:
            return self._resume(scan, odom_pose, stamp, laser_pose)
        if not self._odom:
            start = Pose2D(*self.params.map_start_pose)
            self._map_to_odom = compose(start, inverse(odom_pose))
            return self._add_node(scan, odom_pose, start, stamp, laser_pose, 0.0)
        if stamp < self._stamp:
            raise ValueError(
                f"GridSlam.process: stamp {stamp} is older than the last processed scan {self._stamp}"
            )
        predicted = compose(self._map_to_odom, odom_pose)
        p = self.params
        if not due(p, self._odom[-1], odom_pose, stamp - self._stamp):
            return SlamUpdate(self._map_to_odom, predicted, processed=False)
        points = scan_points(scan, laser_pose, p.max_laser_range)
        pose, response, information = predicted, 0.0, None
        if p.use_scan_matching:
            result, fine = self._match_running_buffer(points, predicted)
            if result is not None and trusted(result):
                stddev = prediction_stddev(p, self._odom[-1], odom_pose)
                pose, information = track(p, self._link_window, result, fine, points, predicted, stddev)
                response = result.response
        update = self._add_node(scan, odom_pose, pose, stamp, laser_pose, response, points, information)
        if p.do_loop_closing and self._try_loop_closure():
            latest = self._poses[-1]
            pose = Pose2D(float(latest[0]), float(latest[1]), float(latest[2]))
            self._map_to_odom = compose(pose, inverse(odom_pose))
            return SlamUpdate(self._map_to_odom, pose, True, response, loop_closed=True)
        return update

    def restart_at(self, pose: Pose2D) -> None:
        """Resume a restored session with the robot at ``pose`` (map frame) on the next scan.

        Why: the saving session's odometry means nothing to the new one, so the next scan is placed
        by matching it against the map around ``pose`` and joins the graph from there.
        """
        self._restart = pose
        self._stamp = -math.inf

    def _resume(self, scan: LaserScan, odom_pose: Pose2D, stamp: float, laser_pose: Pose2D) -> SlamUpdate:
        start, self._restart = self._restart, None
        assert start is not None
        points = scan_points(scan, laser_pose, self.params.max_laser_range)
        result = self._match_running_buffer(points, start)[0]
        if result is None or not trusted(result):
            return self._add_node(scan, odom_pose, start, stamp, laser_pose, 0.0, points)
        return self._add_node(scan, odom_pose, result.pose, stamp, laser_pose, result.response, points)

    def graph(self) -> SlamGraph:
        """The session (nodes, scans, edges, map) for serialization.write_graph."""
        self._advance_rerender(None)
        cell0, log_odds, seen = self._grid.state()
        scans = tuple(scan for scan, _ in self._raw)
        lasers = np.array([laser for _, laser in self._raw], dtype=np.float64).reshape(-1, 3)
        odom = np.array(self._odom, dtype=np.float64).reshape(-1, 3)
        return SlamGraph(self.params, self.poses, odom, scans, lasers, self.edges, cell0, log_odds, seen,
                         self._map_to_odom, self.loop_closures)

    @classmethod
    def from_graph(cls, graph: SlamGraph, params: SlamParams | None = None) -> GridSlam:
        """A mapper holding a saved session, resuming at its first node unless ``restart_at`` says
        otherwise. ``params`` (default: the saved ones) must keep the saved resolution: the map is
        restored cell for cell."""
        slam = cls(params or graph.params)
        if slam.params.resolution != graph.params.resolution:
            raise ValueError(f"the saved graph has resolution {graph.params.resolution} m, the "
                             f"parameters {slam.params.resolution} m")
        slam._poses = np.array(graph.poses, dtype=np.float64).reshape(-1, 3)
        for k, scan in enumerate(graph.scans):
            laser = Pose2D(*map(float, graph.laser_poses[k]))
            points = scan_points(scan, laser, slam.params.max_laser_range)
            slam._raw.append((scan, laser))
            slam._odom.append(Pose2D(*map(float, graph.odom[k])))
            slam._scans.append(points)
            slam._dense.append(joined_returns(points.hits, slam.params.refine_resolution))
            slam._adjacency.append([])
        for edge in graph.edges:
            slam._edges.append(edge)
            slam._adjacency[edge.i].append(edge.j)
            slam._adjacency[edge.j].append(edge.i)
        slam._grid.load(graph.grid_cell0, graph.grid_log_odds, graph.grid_seen)
        slam._map_to_odom, slam.loop_closures = graph.map_to_odom, graph.loop_closures
        if len(slam._poses):
            slam.restart_at(Pose2D(*map(float, slam._poses[0])))
        return slam

    def occupancy(self, complete: bool = True) -> tuple[npt.NDArray[np.int8], GridSpec]:
        """The map as OccupancyGrid values (100 occupied, 0 free, -1 unknown) and its GridSpec (map frame).

        ``complete`` finishes a pending re-render first (its cost grows with the graph: 0.3 s for 1500
        nodes); without it the map is the last complete render, what a node publishes on a budget.
        """
        if complete:
            self._advance_rerender(None)
        return self._grid.occupancy(self.params.occupied_thresh, self.params.free_thresh)

    def _add_node(
        self,
        scan: LaserScan,
        odom_pose: Pose2D,
        pose: Pose2D,
        stamp: float,
        laser_pose: Pose2D,
        response: float,
        points: ScanPoints | None = None,
        information: FloatArray | None = None,
    ) -> SlamUpdate:
        if points is None:
            points = scan_points(scan, laser_pose, self.params.max_laser_range)
        index = len(self._odom)
        self._poses = np.vstack((self._poses, np.array([pose], dtype=np.float64)))
        self._odom.append(odom_pose)
        self._raw.append((scan, laser_pose))
        self._scans.append(points)
        self._dense.append(joined_returns(points.hits, self.params.refine_resolution))
        self._adjacency.append([])
        if index > 0:
            prev = self._poses[index - 1]
            z = between(Pose2D(*prev), pose)
            self._link(index - 1, index, z, information)
        self._stamp = stamp
        self._map_to_odom = compose(pose, inverse(odom_pose))
        if self._rerender is None:  # else the re-render folds this node in
            self._grid.integrate(*points.in_map(pose))
        return SlamUpdate(self._map_to_odom, pose, processed=True, response=response)

    def _link(
        self, i: int, j: int, z: Pose2D, information: FloatArray | None = None, robust: bool = False
    ) -> None:
        """Add edge i → j with ``information`` (default: the fixed link information); loop edges are
        ``robust`` (Cauchy kernel)."""
        info = self._information if information is None else information
        self._edges.append(Edge(i, j, (z.x, z.y, z.yaw), info, robust=robust))
        self._adjacency[i].append(j)
        self._adjacency[j].append(i)

    def _dense_hits_in_map(self, indices: list[int]) -> FloatArray:
        """Joined returns (laser.joined_returns) of the scans ``indices`` in the map: the exact
        reference of the fine refinement."""
        return clouds_in_map(self._dense, self._poses, indices)

    def _match_running_buffer(
        self, points: ScanPoints, predicted: Pose2D
    ) -> tuple[MatchResult | None, CorrelationGrid | None]:
        """Match against the running buffer and, unless it is being re-rendered, the map (tracking.py)."""
        grid = self._grid if self.params.match_against_map and self._rerender is None else None
        return match_running_buffer(
            self.params, self._link_window, self._poses, self._scans, self._dense, grid, points, predicted
        )

    def _try_loop_closure(self) -> bool:
        """Match the newest scan against the nearest unlinked chain within the graph's uncertainty;
        if the match is verified, add a robust edge, re-optimise the whole graph and mark the map
        for a rebuild from the moved nodes."""
        p = self.params
        current = len(self._odom) - 1
        if current - self._last_closure < p.loop_closure_cooldown_nodes:
            return False
        found = search_loop(self._poses, self._adjacency, self._scans, self._dense, p, self._loop_window)
        if found is None or not found.accepted:
            self.loop_closures_rejected += found is not None
            return False
        result = found.result
        self._link(
            found.anchor,
            current,
            between(Pose2D(*self._poses[found.anchor]), result.pose),
            loop_information(result.covariance, result.pose.yaw),
            robust=True,
        )
        optimized = optimize(
            self._poses, self._edges, p.optimizer_max_iterations, kernel_width=p.loop_robust_kernel_width
        )
        moved = float(np.hypot(*(optimized[:, :2] - self._poses[:, :2]).T).max())
        self._poses = optimized
        # Re-rendering costs one integration per node; corrections under half a cell would not change it.
        if moved > 0.5 * p.resolution:
            self._rerender = Rerender(self._new_grid())
        self.loop_closures += 1
        self._last_closure = current
        return True
