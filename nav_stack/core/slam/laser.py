"""Turn a LaserScan into the point sets the mapper keeps per scan, in the robot (base) frame.

Why points in the robot frame: a pose-graph node stores its scan once; after a loop closure moves
the node, the map is rebuilt by transforming the same points with the new pose, so nothing from
the original message (or the TF at that time) has to be kept.

Beam classes (slam_toolbox/Karto semantics):
- a return in ``[range_min, min(range_max, max_laser_range))`` is a *hit*: free along the beam,
  occupied at the endpoint, used for matching;
- +inf, a reading at or beyond ``range_max`` or beyond ``max_laser_range`` is a *miss*: it clears
  along the beam up to the usable range and marks nothing;
- NaN and readings below ``range_min`` (LDS-01 reports 0.0 for "invalid") are dropped.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import FloatArray, Pose2D


@dataclass(frozen=True)
class ScanPoints:
    """One scan in the robot frame.

    Attributes:
        origin: sensor position ``(x, y)`` (m) in the robot frame.
        hits: (K, 2) beam endpoints of returns (m).
        misses: (J, 2) points at the usable range along beams that returned nothing (m).
    """

    origin: tuple[float, float]
    hits: FloatArray
    misses: FloatArray

    def in_map(self, pose: Pose2D) -> tuple[tuple[float, float], FloatArray, FloatArray]:
        """Sensor origin, hits and misses transformed by the robot ``pose`` in the map frame."""
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        ox = pose.x + c * self.origin[0] - s * self.origin[1]
        oy = pose.y + s * self.origin[0] + c * self.origin[1]
        return (ox, oy), to_map(self.hits, pose), to_map(self.misses, pose)


def to_map(points: FloatArray, pose: Pose2D) -> FloatArray:
    """Robot-frame ``points`` (K, 2) seen from the robot ``pose``, in the map frame (m)."""
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    return np.asarray(points @ np.array([[c, s], [-s, c]]) + np.array([pose.x, pose.y]), dtype=np.float64)


def clouds_in_map(clouds: Sequence[FloatArray], poses: FloatArray, indices: Sequence[int]) -> FloatArray:
    """The robot-frame point sets ``clouds[k]`` of the nodes ``indices``, each seen from its pose
    ``poses[k]`` ((N, 3), map frame), stacked (m): a reference for the matcher."""
    parts = [to_map(clouds[k], Pose2D(*poses[k])) for k in indices]
    return np.vstack(parts) if parts else np.zeros((0, 2))


def scan_points(scan: LaserScan, laser_pose: Pose2D, max_laser_range: float) -> ScanPoints:
    """Classify the beams of ``scan`` and express them in the robot frame.

    ``laser_pose`` is the sensor's pose in the robot frame (base_footprint → base_scan, from TF).
    """
    usable = min(max_laser_range, scan.range_max)
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    angles = scan.angles + laser_pose.yaw
    with np.errstate(invalid="ignore"):
        hit = (ranges >= scan.range_min) & (ranges < usable)
        miss = ~hit & ~np.isnan(ranges) & (ranges >= usable)
    cos, sin = np.cos(angles), np.sin(angles)
    hits = np.column_stack((laser_pose.x + ranges[hit] * cos[hit], laser_pose.y + ranges[hit] * sin[hit]))
    misses = np.column_stack((laser_pose.x + usable * cos[miss], laser_pose.y + usable * sin[miss]))
    return ScanPoints((laser_pose.x, laser_pose.y), hits, misses)


# Neighbouring returns closer than this (m) lie on one surface and are joined for the refinement.
JOIN_GAP = 0.15


def joined_returns(hits: FloatArray, refine_resolution: float) -> FloatArray:
    """The hits of one scan joined into lines for the refinement grid of ``refine_resolution`` (m)."""
    return densify(hits, 0.5 * refine_resolution, JOIN_GAP)


def densify(hits: FloatArray, spacing: float, max_gap: float) -> FloatArray:
    """Hits (K, 2, beam order) followed by points added between neighbours closer than ``max_gap``
    (m), evenly, so that no two consecutive points along a joined pair lie over ``spacing`` (m) apart.

    Why: a fine likelihood field built from the beam endpoints alone is a row of dots along each
    wall (1° beams are 3-6 cm apart at 2-3 m), and a scan refined against it locks onto the dots
    instead of the wall. Joining neighbouring returns turns each wall back into a line.
    """
    if len(hits) < 2:
        return hits
    a, b = hits[:-1], hits[1:]
    gap = np.hypot(*(b - a).T)
    keep = (gap < max_gap) & (gap > spacing)
    counts = np.floor(gap[keep] / spacing).astype(np.int64)
    if counts.sum() == 0:
        return hits
    seg = np.repeat(np.flatnonzero(keep), counts)
    within = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    f = ((within + 1) / (np.repeat(counts, counts) + 1))[:, None]
    return np.vstack((hits, a[seg] + f * (b[seg] - a[seg])))
