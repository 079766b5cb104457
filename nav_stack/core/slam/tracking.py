"""Scan-to-reference tracking: where a new scan is matched when no loop is being closed.

Why a module of its own: the mapper (mapper.py) owns the graph and the map; what it matches each
processed scan against is a separate decision with its own trade-offs, kept here:

- the search reference is the running buffer (the last ``scan_buffer_size`` scans within
  ``scan_buffer_maximum_scan_distance``) plus, unless the map is being re-rendered from moved
  poses, the map's occupied cells within laser range: the buffer alone drifts about 1 % of the
  distance driven, and the map, averaged over every scan, holds the frame still between closures;
- the refinement reference is the buffer's and the nearest scans' joined returns (exact points,
  where the map's cells are quantised and two or three cells thick);
- where the match is ambiguous (a corridor seen without its ends), the prediction is kept along
  the ambiguous direction (``tracked_pose``): the match is biased backwards there and lagged the
  true motion by 17-25 % along corridors longer than the laser range; the returns facing that
  direction (a pillar, a door frame) correct the prediction in proportion to what they fix
  (match_information.along_axis);
- each sequential edge is as certain, direction by direction, as what placed its end
  (``link_information``: the refined peak's curvature, or the prediction and the facing returns).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam.correlation import CorrelationGrid, MatchResult, SearchWindow
from nav_stack.core.slam.laser import JOIN_GAP, ScanPoints, clouds_in_map
from nav_stack.core.slam.log_odds import LogOddsGrid
from nav_stack.core.slam.match_information import AlongAxis, along_axis, peak_information
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.shared import between, loop_information, match_scan_on_grids, subsample

# Below this mean smear the running-buffer match is not trusted and odometry is kept
# (slam_toolbox's link_match_minimum_response_fine default).
MIN_LINK_RESPONSE = 0.1
# At most this many scans near the robot (besides the running buffer) are refined against.
MAX_REFINE_NODES = 30
# A direction of the matched position whose standard deviation (m, MatchResult.covariance) exceeds
# this is degenerate and keeps the prediction. A distinct peak reports the coarse grid's floor
# (0.05 m on 5 cm cells) to about 0.10 m; a corridor seen without its ends 0.13 m or more along it
# (the spread of the near-best candidates of a ±0.25 m window). Same bound as a loop closure's.
MAX_CONSTRAINED_STDDEV = 0.1
# Floors of a matched link's standard deviations (m, rad): about the true per-link errors on the
# benchmark worlds (0.001 m, 0.0007 rad), so no link is stiffer than what matching achieves.
MIN_LINK_STDDEV = 0.002
MIN_LINK_YAW_STDDEV = 0.0005


def match_running_buffer(
    params: SlamParams,
    window: SearchWindow,
    poses: FloatArray,
    scans: Sequence[ScanPoints],
    joined: Sequence[FloatArray],
    grid: LogOddsGrid | None,
    points: ScanPoints,
    predicted: Pose2D,
) -> tuple[MatchResult | None, CorrelationGrid | None]:
    """Match ``points`` around ``predicted`` (map frame) against the running buffer, and ``grid``'s
    occupied cells when given (None while the map is re-rendered: its poses are stale).

    ``poses`` (N, 3) are the graph's nodes, ``scans`` and ``joined`` (laser.joined_returns) their
    returns, ``window`` the running-buffer search window. None when a side has too few points.
    """
    p = params
    n = len(poses)
    d = np.hypot(poses[:, 0] - predicted.x, poses[:, 1] - predicted.y)
    recent = range(max(0, n - p.scan_buffer_size), n)
    buffer = [k for k in recent if d[k] <= p.scan_buffer_maximum_scan_distance]
    reference = clouds_in_map([scan.hits for scan in scans], poses, buffer)
    if grid is not None:
        half = p.max_laser_range + window.half_extent
        near = grid.occupied_points((predicted.x, predicted.y), half, p.occupied_thresh)
        reference = np.vstack((reference, near))
    close = np.argsort(d)[:MAX_REFINE_NODES]
    close = close[d[close] <= p.refine_scan_distance]
    fine_reference = clouds_in_map(joined, poses, sorted(set(close.tolist()) | set(buffer)))
    return match_scan_on_grids(p, reference, points.hits, predicted, window, fine_reference)


def trusted(result: MatchResult | None) -> bool:
    """Whether a running-buffer match replaces the odometry prediction."""
    return result is not None and result.response >= MIN_LINK_RESPONSE


def degenerate_axes(result: MatchResult) -> list[FloatArray]:
    """Unit directions (map frame) of the matched position whose coarse standard deviation
    (MatchResult.covariance) exceeds MAX_CONSTRAINED_STDDEV."""
    variances, vectors = np.linalg.eigh(result.covariance[:2, :2])
    return [vectors[:, k] for k in range(2) if variances[k] > MAX_CONSTRAINED_STDDEV**2]


def prediction_stddev(params: SlamParams, last_odom: Pose2D, odom_pose: Pose2D) -> float:
    """Standard deviation (m) of the odometry prediction's position since the last processed scan:
    ``odometry_translation_noise`` times the distance travelled."""
    moved = between(last_odom, odom_pose)
    return params.odometry_translation_noise * math.hypot(moved.x, moved.y)


@dataclass(frozen=True)
class MatchInformation:
    """What a running-buffer match says per direction (match_information.py): the refined peak's
    information (3 × 3, m⁻² and rad⁻², map frame; zero without a refinement grid) and the fit of
    the facing returns along each degenerate axis."""

    peak: FloatArray
    along: list[AlongAxis]


def measure(
    params: SlamParams,
    window: SearchWindow,
    result: MatchResult,
    fine: CorrelationGrid | None,
    points: ScanPoints,
    predicted: Pose2D,
    stddev: float,
) -> MatchInformation:
    """The information of ``result`` (matched on the refinement grid ``fine``; nothing is measured
    without it) and the fits along its degenerate axes about ``predicted`` of ``stddev`` (m)."""
    axes = degenerate_axes(result)
    if fine is None:
        return MatchInformation(np.zeros((3, 3)), [AlongAxis(u) for u in axes])
    hits = subsample(points.hits, params.max_scan_points)
    peak = peak_information(fine, hits, result.pose, result.covariance, window.fine_angle_resolution)
    if stddev <= 0.0:
        return MatchInformation(peak, [AlongAxis(u) for u in axes])
    return MatchInformation(
        peak, [along_axis(fine, hits, result.pose, predicted, u, stddev, JOIN_GAP) for u in axes]
    )


def tracked_pose(
    result: MatchResult, predicted: Pose2D, along: Sequence[AlongAxis] | None = None
) -> MatchResult:
    """``result`` with its position along every degenerate direction taken from ``predicted``
    (odometry), moved by the correction of the returns facing that direction (``along``, from
    measure; None: no correction). Well-constrained directions and the yaw are the match's.

    Why (degeneracy-aware matching, Zhang, Kaess and Singh 2016): along a featureless corridor the
    scan says nothing about the position, yet the match is not neutral there. The reference (the
    buffer's scans and the map) ends where earlier scans reached and thins out towards that end
    (grazing returns 0.2 m apart, seen by the newest scans only), while the new scan reaches a step
    further: sliding it back raises its score by more than the distance penalty costs. On a 16 m
    corridor the matched pose advanced 77 % of the distance driven, where odometry (random scale
    noise, no bias along the axis) advanced 99 %. Where the scan pins the position (a corner, an
    end wall, a door) the spread is small in every direction and the match is kept whole.

    Why the correction: a lone pillar or a door frame in view does fix the position along the
    corridor, but it is a few beams among hundreds and does not narrow the coarse spread. Its
    returns are found by their surface facing the axis (match_information.py) and fitted without
    the side walls' (which cause the bias). Without it, the pose rested on odometry along the
    whole corridor: a lap of bench_slam's 24 m corridor ring (5 % odometry) drifted 0.14 m before
    its first closure (0.10 m with it, seeds 2 and 3), test_slam_refinement's ring lap (8 %) 0.20 m
    (0.08 m with it). Fitting the whole match instead, side walls included, drifted 0.59 m.
    Loop closures are unaffected: they reject ambiguous matches (loop_closure.verified).
    """
    fits = [AlongAxis(u) for u in degenerate_axes(result)] if along is None else list(along)
    if not fits:
        return result
    x, y = result.pose.x, result.pose.y
    for fit in fits:
        u = fit.axis
        step = float(u @ np.array([predicted.x - x, predicted.y - y])) + fit.correction
        x, y = x + step * float(u[0]), y + step * float(u[1])
    return replace(result, pose=Pose2D(x, y, result.pose.yaw))


def link_information(
    params: SlamParams, result: MatchResult, measured: MatchInformation, stddev: float, yaw: float
) -> FloatArray:
    """Information (3 × 3, in the new node's frame at ``yaw``, rad) of a sequential edge whose end
    was placed by the running-buffer match ``result`` (tracked_pose) from a prediction of
    ``stddev`` (m), with what the match ``measured``.

    Each direction is as certain as what placed the edge's end (match_information.py): where the
    match fixed the position and for the yaw, the refined peak's curvature; along a degenerate
    direction, the prediction's and the facing returns' information together. Weighted so, a loop
    closure's correction goes where the drift is (the corridors' lengths) instead of bending the
    lap through its yaw. Variances are floored at MIN_LINK_STDDEV / MIN_LINK_YAW_STDDEV; without a
    measurement they fall back to the coarse spread and ``link_stddev_yaw``.
    """
    variances, vectors = np.linalg.eigh(result.covariance[:2, :2])
    fits = {tuple(np.round(fit.axis, 12)): fit for fit in measured.along}
    floor = MIN_LINK_STDDEV**2
    link_var = np.empty(2)
    for k in range(2):
        u = vectors[:, k]
        if variances[k] > MAX_CONSTRAINED_STDDEV**2:
            fit = fits.get(tuple(np.round(u, 12)), AlongAxis(u))
            prior = stddev**-2 if stddev > 0.0 else 1.0 / floor
            link_var[k] = max(1.0 / (prior + fit.information), floor)
        else:
            info = float(u @ measured.peak[:2, :2] @ u)
            link_var[k] = max(1.0 / info, floor) if info > 0.0 else variances[k]
    link = np.zeros((3, 3))
    link[:2, :2] = vectors @ np.diag(link_var) @ vectors.T
    yaw_info = measured.peak[2, 2]
    link[2, 2] = max(1.0 / yaw_info, MIN_LINK_YAW_STDDEV**2) if yaw_info > 0.0 else params.link_stddev_yaw**2
    return loop_information(link, yaw)


def track(
    params: SlamParams,
    window: SearchWindow,
    result: MatchResult,
    fine: CorrelationGrid | None,
    points: ScanPoints,
    predicted: Pose2D,
    stddev: float,
) -> tuple[Pose2D, FloatArray]:
    """The pose (map frame) of a trusted running-buffer match ``result`` of ``points`` (tracked_pose)
    and the information of the sequential edge to it (link_information), from ``predicted`` of
    ``stddev`` (m) and the refinement grid ``fine`` the match ran on (match_running_buffer)."""
    measured = measure(params, window, result, fine, points, predicted, stddev)
    pose = tracked_pose(result, predicted, measured.along).pose
    return pose, link_information(params, result, measured, stddev, pose.yaw)
