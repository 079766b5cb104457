"""What the mapper and the localizer share: SE(2) pose algebra (m, rad), input checks, the
per-scan result, and one correlative scan match with the SLAM parameters.

Why a module of its own: mapping (mapper.py: running buffer, loop closures) and localization on a
saved graph (localization.py) build different references but must search them identically (same
smear, window and refinement grid) and turn a matched pose into the map → odom correction the same
way, or localizing on a saved graph would not reproduce the map's own geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.geometry import IDENTITY, FloatArray, Pose2D, to_frame
from nav_stack.core.slam.correlation import CorrelationGrid, MatchResult, SearchWindow, match
from nav_stack.core.slam.params import SlamParams

# Fewer usable reference or scan points than this make a match meaningless.
MIN_MATCH_POINTS = 20


def between(a: Pose2D, b: Pose2D) -> Pose2D:
    """Pose ``b`` expressed in the frame of pose ``a`` (a⁻¹ ∘ b)."""
    x, y, yaw = to_frame(np.array([b], dtype=np.float64), a)[0]
    return Pose2D(float(x), float(y), float(yaw))


def inverse(a: Pose2D) -> Pose2D:
    """The inverse transform a⁻¹."""
    return between(a, IDENTITY)


def loop_information(covariance: FloatArray, yaw: float) -> FloatArray:
    """Information of a loop edge anchor → j from the covariance (map frame) of j's matched pose.

    The edge error t2v(Z⁻¹ Xi⁻¹ Xj) moves with Xj in Xj's own frame, so the covariance is rotated
    by node j's ``yaw`` (rad) before it is inverted. (Rotating by the anchor's yaw, as before,
    swapped the along- and across-corridor variances of a closure made at a right angle.)
    """
    c, s = math.cos(yaw), math.sin(yaw)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return np.asarray(np.linalg.inv(rot.T @ covariance @ rot), dtype=np.float64)


def check_inputs(odom_pose: Pose2D, laser_pose: Pose2D, stamp: float) -> None:
    """Raise ValueError naming the input when a pose or the stamp (s) is not finite."""
    for name, value in (("odom_pose", odom_pose), ("laser_pose", laser_pose)):
        if not all(math.isfinite(v) for v in value):
            raise ValueError(f"GridSlam.process: {name} must be finite, got {tuple(value)}")
    if not math.isfinite(stamp):
        raise ValueError(f"GridSlam.process: stamp must be finite, got {stamp}")


def due(params: SlamParams, last_odom: Pose2D, odom_pose: Pose2D, elapsed: float) -> bool:
    """Whether a scan is processed: the robot moved ``minimum_travel_distance`` (m) or turned
    ``minimum_travel_heading`` (rad) since ``last_odom``, ``elapsed`` (s) after the last processed one
    is at least ``minimum_time_interval``. Scans in between only update the reported pose."""
    moved = between(last_odom, odom_pose)
    far_enough = (
        math.hypot(moved.x, moved.y) >= params.minimum_travel_distance
        or abs(moved.yaw) >= params.minimum_travel_heading
    )
    return far_enough and elapsed >= params.minimum_time_interval


@dataclass(frozen=True)
class SlamUpdate:
    """What one ``process`` call produced.

    Attributes:
        map_to_odom: the correction to publish as the map → odom transform.
        pose: robot (base frame) pose in the map.
        processed: the scan was matched (mapping: it became a pose-graph node; localization: it
            corrected map → odom); else it only refreshed ``pose``.
        response: scan-match response in [0, 1] of a processed scan (0 when not matched).
        loop_closed: a loop closure was accepted on this scan.
    """

    map_to_odom: Pose2D
    pose: Pose2D
    processed: bool
    response: float = 0.0
    loop_closed: bool = False


def subsample(hits: FloatArray, max_points: int) -> FloatArray:
    """Every k-th of the (K, 2) ``hits`` so that at most ``max_points`` remain (bounds the cost)."""
    step = max(1, math.ceil(len(hits) / max_points))
    return hits[::step]


def match_scan(
    params: SlamParams,
    reference: FloatArray,
    hits: FloatArray,
    prior: Pose2D,
    window: SearchWindow,
    fine_reference: FloatArray | None = None,
) -> MatchResult | None:
    """Match ``hits`` (robot frame, m) against ``reference`` (map frame, m) around ``prior``.

    The search grid has the map's resolution and ``correlation_search_space_smear_deviation``; the
    refinement (when ``window.refine_iterations`` > 0) runs on ``fine_reference`` (default: the
    reference) at ``refine_resolution`` / ``refine_smear_deviation``. None when either side has
    fewer than MIN_MATCH_POINTS points.
    """
    return match_scan_on_grids(params, reference, hits, prior, window, fine_reference)[0]


def match_scan_on_grids(
    params: SlamParams,
    reference: FloatArray,
    hits: FloatArray,
    prior: Pose2D,
    window: SearchWindow,
    fine_reference: FloatArray | None = None,
) -> tuple[MatchResult | None, CorrelationGrid | None]:
    """``match_scan`` and the refinement grid it ran on (None without refinement or match)."""
    if len(reference) < MIN_MATCH_POINTS or len(hits) < MIN_MATCH_POINTS:
        return None, None
    p = params
    half = p.max_laser_range + window.half_extent + 3.0 * p.correlation_search_space_smear_deviation
    grid = CorrelationGrid(
        reference, (prior.x, prior.y), half, p.resolution, p.correlation_search_space_smear_deviation
    )
    fine = None
    if window.refine_iterations > 0:
        fine_half = p.max_laser_range + window.half_extent + 3.0 * p.refine_smear_deviation
        fine = CorrelationGrid(
            reference if fine_reference is None else fine_reference,
            (prior.x, prior.y),
            fine_half,
            p.refine_resolution,
            p.refine_smear_deviation,
        )
    return match(grid, subsample(hits, p.max_scan_points), prior, window, fine), fine
