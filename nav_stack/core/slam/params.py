"""Parameters of the grid SLAM, named after slam_toolbox's where slam_toolbox has the same knob.

Why one dataclass: the SLAM node declares every field as a ROS parameter with this default, so
defaults live here only. Deviations from slam_toolbox's yaml (mapper_params_online_async.yaml) are
deliberate and explained per field: the brief asks for 0.2 m / 0.2 rad travel thresholds, and the
loop-closure search window is smaller because the correlative search runs in numpy, not C++.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields


@dataclass(frozen=True)
class SlamParams:
    """Grid SLAM knobs (SI units: m, rad, s).

    Mapping:
        resolution: map cell size (m).
        max_laser_range: beams are used up to this range (m); longer or missing returns only clear.
        minimum_travel_distance / minimum_travel_heading: a scan is processed once the robot moved
            this far (m) or turned this much (rad) since the last processed scan.
        minimum_time_interval: and at least this long (s) after it.
        map_update_interval: period (s) at which the ROS node republishes /map (the core renders
            on demand through ``GridSlam.occupancy()``; after a loop closure the re-render goes
            a slice of nodes per scan, rerender.py).
        map_start_pose: ``(x, y, yaw)`` of the robot's first pose in the map frame; (-2.0, -0.5, 0)
            puts the map in turtlebot3_world's frame.
        hit_probability / miss_probability: occupancy evidence of a beam endpoint / a traversed cell.
        clamp_min_probability / clamp_max_probability: log-odds clamping, keeps cells able to change.
        occupied_thresh / free_thresh: probability thresholds of the trinary map (map_saver names).

    Scan matching (slam_toolbox's correlative matcher):
        use_scan_matching: correct odometry by matching scans; false = pure odometry mapping.
        scan_buffer_size / scan_buffer_maximum_scan_distance: the running buffer of recent scans
            (count, m) the new scan is matched against.
        match_against_map: also match against the occupied cells of the map built so far (within
            laser range). Not a slam_toolbox knob: the running buffer alone drifts about 1 % of the
            distance driven (0.1 m over one lap of turtlebot3_world), and the map, averaged over
            every scan, holds the frame still between loop closures.
        correlation_search_space_dimension: side (m) of the square translation search window.
        correlation_search_space_smear_deviation: σ (m) of the Gaussian smear of reference points.
        coarse_search_angle_offset / coarse_angle_resolution: ± yaw window and coarse yaw step (rad).
        fine_search_angle_offset: fine yaw step (rad), searched within ± one coarse step.
        distance_variance_penalty / angle_variance_penalty: how fast the response is penalised
            for moving away from the odometry prediction (m², rad²); minimum_distance_penalty /
            minimum_angle_penalty: floors of those multiplicative penalties.
        refine_iterations: pattern-search steps on the bilinear-interpolated smear after the grid
            search (0 disables sub-cell refinement).
        refine_resolution / refine_smear_deviation: cell size (m) and smear σ (m) of the finer
            grid of the same reference points the refinement runs on. The search grid (map
            resolution, σ 0.1 m) is flat within a few cm, which lets the pose wander along
            corridors; slam_toolbox searches on a 0.01 m grid for the same reason.
        refine_scan_distance: scans of the graph within this distance (m) of the prediction (the
            nearest 30) join the running buffer as the refinement's reference, their returns
            joined into lines: exact points, where the map's occupied cells are quantised to
            whole cells and two or three cells thick.
        max_scan_points: beams kept for matching (evenly subsampled; bounds the cost).
        odometry_translation_noise: standard deviation of odometry's position per metre travelled
            (relative, like AMCL's odom_alpha3): the prediction's uncertainty along a direction the
            match leaves degenerate, weighed against the returns facing it (degeneracy.py); 0 keeps
            the prediction there. Not a slam_toolbox knob.

    Loop closure:
        do_loop_closing: search older scans near the robot for loop closures.
        loop_search_maximum_distance: older poses within this distance (m) are candidates.
        loop_match_minimum_chain_size: candidates must form a chain of this many consecutive scans.
        loop_match_minimum_response_coarse / _fine: response (0..1) needed to accept a closure.
        loop_match_maximum_stddev: largest standard deviation (m) of the matched position, from
            the spread of the near-best candidates, for a closure to be accepted: rejects matches
            that fit equally well at several offsets (corridors, repeated features). slam_toolbox's
            loop_match_maximum_variance_coarse plays this role in its own (cell) units.
        loop_search_space_dimension: largest side (m) of the loop translation window (slam_toolbox:
            8.0); the window actually searched is three standard deviations of the graph's drift
            between the chain and the new scan, at least the running-buffer window.
        loop_robust_kernel_width: width c (standard deviations) of the Cauchy kernel that down-weights
            loop edges the rest of the graph contradicts (not a slam_toolbox knob).
        loop_closure_cooldown_nodes: processed scans to wait after an accepted closure before
            searching again (bounds the cost of revisiting an area; not a slam_toolbox knob).
        link_stddev_xy / link_stddev_yaw: standard deviation (m, rad) of a sequential pose-graph
            constraint where the scan was not matched (odometry only), and the drift per link the
            loop search window assumes; a matched link takes the refined match's own information
            (tracking.link_information), loop edges the match's covariance.
        optimizer_max_iterations: Gauss-Newton iterations of the pose-graph solve.
    """

    resolution: float = 0.05
    max_laser_range: float = 3.5
    minimum_travel_distance: float = 0.2
    minimum_travel_heading: float = 0.2
    minimum_time_interval: float = 0.0
    map_update_interval: float = 5.0
    map_start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    hit_probability: float = 0.7
    miss_probability: float = 0.4
    clamp_min_probability: float = 0.12
    clamp_max_probability: float = 0.97
    occupied_thresh: float = 0.65
    free_thresh: float = 0.25

    use_scan_matching: bool = True
    scan_buffer_size: int = 10
    scan_buffer_maximum_scan_distance: float = 10.0
    match_against_map: bool = True
    correlation_search_space_dimension: float = 0.5
    correlation_search_space_smear_deviation: float = 0.1
    coarse_search_angle_offset: float = 0.349
    coarse_angle_resolution: float = 0.0349
    fine_search_angle_offset: float = 0.00349
    distance_variance_penalty: float = 0.5
    angle_variance_penalty: float = 1.0
    minimum_distance_penalty: float = 0.5
    minimum_angle_penalty: float = 0.9
    refine_iterations: int = 14
    refine_resolution: float = 0.02
    refine_smear_deviation: float = 0.03
    refine_scan_distance: float = 0.5
    max_scan_points: int = 360
    odometry_translation_noise: float = 0.05

    do_loop_closing: bool = True
    loop_search_maximum_distance: float = 3.0
    loop_match_minimum_chain_size: int = 10
    loop_match_minimum_response_coarse: float = 0.35
    loop_match_minimum_response_fine: float = 0.45
    loop_match_maximum_stddev: float = 0.1
    loop_search_space_dimension: float = 2.0
    loop_robust_kernel_width: float = 1.0
    loop_closure_cooldown_nodes: int = 10
    link_stddev_xy: float = 0.05
    link_stddev_yaw: float = 0.02
    optimizer_max_iterations: int = 10

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "map_start_pose":
                if len(value) != 3 or not all(math.isfinite(v) for v in value):
                    raise ValueError(
                        f"SlamParams.map_start_pose must be 3 finite numbers [x, y, yaw], got {value}"
                    )
            elif isinstance(value, bool):
                continue
            elif not math.isfinite(value) or value < 0:
                raise ValueError(f"SlamParams.{f.name} must be a finite number >= 0, got {value}")
        positive = (
            "resolution",
            "max_laser_range",
            "correlation_search_space_dimension",
            "correlation_search_space_smear_deviation",
            "refine_resolution",
            "refine_smear_deviation",
            "coarse_angle_resolution",
            "fine_search_angle_offset",
            "distance_variance_penalty",
            "angle_variance_penalty",
            "link_stddev_xy",
            "link_stddev_yaw",
            "scan_buffer_size",
            "max_scan_points",
            "loop_search_space_dimension",
            "loop_match_maximum_stddev",
            "loop_robust_kernel_width",
        )
        for name in positive:
            if getattr(self, name) <= 0:
                raise ValueError(f"SlamParams.{name} must be > 0, got {getattr(self, name)}")
        for name in (
            "hit_probability",
            "miss_probability",
            "clamp_min_probability",
            "clamp_max_probability",
            "occupied_thresh",
            "free_thresh",
        ):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(f"SlamParams.{name} must lie in (0, 1), got {getattr(self, name)}")
        for name in ("minimum_distance_penalty", "minimum_angle_penalty"):
            if getattr(self, name) > 1.0:
                raise ValueError(f"SlamParams.{name} must lie in [0, 1], got {getattr(self, name)}")
        if not self.miss_probability < 0.5 < self.hit_probability:
            raise ValueError(
                f"SlamParams needs miss_probability < 0.5 < hit_probability, got "
                f"{self.miss_probability}, {self.hit_probability}"
            )
        if not self.free_thresh < self.occupied_thresh:
            raise ValueError(
                f"SlamParams needs free_thresh < occupied_thresh, got {self.free_thresh}, "
                f"{self.occupied_thresh}"
            )
        if not self.clamp_min_probability < self.clamp_max_probability:
            raise ValueError(
                f"SlamParams needs clamp_min_probability < clamp_max_probability, got "
                f"{self.clamp_min_probability}, {self.clamp_max_probability}"
            )
