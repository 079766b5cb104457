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
  true motion by 17-25 % along corridors longer than the laser range.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam.correlation import MatchResult, SearchWindow
from nav_stack.core.slam.laser import ScanPoints, clouds_in_map
from nav_stack.core.slam.log_odds import LogOddsGrid
from nav_stack.core.slam.params import SlamParams
from nav_stack.core.slam.shared import loop_information, match_scan

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


def match_running_buffer(
    params: SlamParams,
    window: SearchWindow,
    poses: FloatArray,
    scans: Sequence[ScanPoints],
    joined: Sequence[FloatArray],
    grid: LogOddsGrid | None,
    points: ScanPoints,
    predicted: Pose2D,
) -> MatchResult | None:
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
    return match_scan(p, reference, points.hits, predicted, window, fine_reference)


def trusted(result: MatchResult | None) -> bool:
    """Whether a running-buffer match replaces the odometry prediction."""
    return result is not None and result.response >= MIN_LINK_RESPONSE


def tracked_pose(result: MatchResult, predicted: Pose2D) -> MatchResult:
    """``result`` with its position kept at ``predicted``'s (odometry) along every degenerate
    direction: an eigenvector of the match's position covariance (m², map frame) whose standard
    deviation exceeds MAX_CONSTRAINED_STDDEV. Well-constrained directions and the yaw are the match's.

    Why (degeneracy-aware matching, Zhang, Kaess and Singh 2016): along a featureless corridor the
    scan says nothing about the position, yet the match is not neutral there. The reference (the
    buffer's scans and the map) ends where earlier scans reached and thins out towards that end
    (grazing returns 0.2 m apart, seen by the newest scans only), while the new scan reaches a step
    further: sliding it back raises its score by more than the distance penalty costs. On a 16 m
    corridor the matched pose advanced 77 % of the distance driven, where odometry (random scale
    noise, no bias along the axis) advanced 99 %. Where the scan pins the position (a corner, an
    end wall, a door) the spread is small in every direction and the match is kept whole.

    Cost: a lone small pillar (a few beams) does not narrow the coarse spread, so along such a
    corridor the pose rests on odometry too; with poor odometry (8 % scale noise per step) that
    drifts more than the pillar-anchored match did (test_slam_refinement's ring lap).
    Loop closures are unaffected: they reject ambiguous matches (loop_closure.verified).
    """
    variances, vectors = np.linalg.eigh(result.covariance[:2, :2])
    constrained = vectors[:, variances <= MAX_CONSTRAINED_STDDEV**2]
    if constrained.shape[1] == 2:
        return result
    delta = np.array([result.pose.x - predicted.x, result.pose.y - predicted.y])
    kept = constrained @ (constrained.T @ delta)
    pose = Pose2D(predicted.x + float(kept[0]), predicted.y + float(kept[1]), result.pose.yaw)
    return replace(result, pose=pose)


def link_information(params: SlamParams, covariance: FloatArray, yaw: float) -> FloatArray:
    """Information (3 × 3, in the new node's frame at ``yaw``, rad) of a sequential edge whose end
    was placed by a running-buffer match of position ``covariance`` (m², map frame).

    Why not the fixed ``link_stddev_xy`` in every direction: along a degenerate direction the edge
    carries odometry (tracked_pose), not a match, and is as uncertain as the spread of the match
    says. Weighted so, a loop closure's correction goes mostly into the corridors' lengths, where
    the drift is, instead of being spread evenly over well-matched directions. Each positional
    variance is floored at ``link_stddev_xy``²; the yaw keeps ``link_stddev_yaw``.
    """
    variances, vectors = np.linalg.eigh(covariance[:2, :2])
    link = np.zeros((3, 3))
    link[:2, :2] = vectors @ np.diag(np.maximum(variances, params.link_stddev_xy**2)) @ vectors.T
    link[2, 2] = params.link_stddev_yaw**2
    return loop_information(link, yaw)
