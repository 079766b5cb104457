"""What a refined running-buffer match says about each direction: the curvature of its peak, and
along a direction it leaves degenerate, the fit of the returns that face that direction.

Why the curvature (``peak_information``): the refinement grid's smear is each return's likelihood
under a Gaussian of the smear deviation, so N times the curvature of the mean smear at the refined
pose is the Fisher information of the pose (m⁻², rad⁻²). On the benchmark worlds it gives 0.003 m
and 0.002 rad per link where the true errors are 0.001 m and 0.0007 rad, in proportion in every
direction, where the fixed link_stddev_xy / link_stddev_yaw (0.05 m, 0.02 rad) left the yaw
relatively loose: a loop closure then bent the lap through its yaw instead of stretching the
corridors it drifted along.

Why the facing returns (``along_axis``): along a corridor the correlative match is degenerate (its
coarse spread is wide along the axis) and biased backwards: the side walls' returns, grazing and
a dotted line at the far end of the reference, score higher when the scan slides back
(tracking.tracked_pose). Yet a pillar, a door frame or an end wall in view does fix the position
along the axis. Its returns are the ones whose surface faces along the axis; the side walls' face
across it and say nothing along it. So the position along the axis is searched on the refinement
grid with the facing returns only, about the odometry prediction, and weighed against the
prediction by the curvature of that search. Zhang, Kaess and Singh (2016) make the same split:
solve in the well-conditioned directions, keep the prior in the others.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.slam.correlation import CorrelationGrid

# A return faces the axis when its surface normal is within 60° of it (|cos| >= 0.5).
MIN_FACING_COSINE = 0.5
# Fewer facing returns than this do not measure the position along the axis.
MIN_FACING_POINTS = 3
# The search along the axis: ± this many standard deviations of the prediction, in steps of half
# a refinement cell.
SEARCH_STDDEVS = 4.0


@dataclass(frozen=True)
class AlongAxis:
    """The position along a degenerate ``axis`` (unit, map frame): ``offset`` (m) from the prediction
    to the best fit of the facing returns, its ``information`` (m⁻²; 0 when they do not fix it),
    and the ``correction`` (m) applied to the prediction, the offset weighted by the information
    against the prediction's."""

    axis: FloatArray
    offset: float = 0.0
    information: float = 0.0
    correction: float = 0.0


def peak_information(
    grid: CorrelationGrid, points: FloatArray, pose: Pose2D, covariance: FloatArray, yaw_step: float
) -> FloatArray:
    """Information (3 × 3, m⁻² and rad⁻², map frame) of the refined ``pose`` of ``points`` (robot
    frame) on ``grid``: along each axis of ``covariance``'s position block (the coarse spread) and
    along the yaw, N · (−r″) with r″ the second difference of the mean smear over one cell (one
    ``yaw_step``, rad). A direction where the response does not fall on both sides counts 0.
    """
    _, vectors = np.linalg.eigh(covariance[:2, :2])
    axes = np.zeros((3, 3))
    axes[:2, :2] = vectors.T
    axes[2, 2] = 1.0
    steps = np.array([grid.resolution, grid.resolution, yaw_step])
    centre = np.array(pose, dtype=np.float64)
    moves = axes * steps[:, None]
    values = grid.mean_smear(points, np.vstack((centre, centre + moves, centre - moves)))
    drop = np.minimum(values[0] - values[1:4], values[0] - values[4:7])
    curvature = len(points) * 2.0 * np.maximum(drop, 0.0) / steps**2
    return np.asarray(axes.T @ np.diag(curvature) @ axes, dtype=np.float64)


def facing(hits: FloatArray, axis: FloatArray, max_gap: float) -> npt.NDArray[np.bool_]:
    """Which of the ``hits`` (K, 2, robot frame, beam order) lie on a surface facing ``axis`` (unit,
    robot frame): the normal of the chord between their neighbours (both closer than ``max_gap``
    m, else the one that is) within acos(MIN_FACING_COSINE) of the axis."""
    k = len(hits)
    out = np.zeros(k, dtype=bool)
    if k < 3:
        return out
    gap = np.hypot(*(hits[1:] - hits[:-1]).T)
    joined = gap < max_gap  # hits i and i + 1 lie on one surface
    has_prev = np.concatenate(([False], joined))
    has_next = np.concatenate((joined, [False]))
    prev = np.where(has_prev[:, None], np.roll(hits, 1, axis=0), hits)
    nxt = np.where(has_next[:, None], np.roll(hits, -1, axis=0), hits)
    tangent = nxt - prev
    length = np.hypot(*tangent.T)
    ok = length > 1e-9
    normal_dot = np.abs(-tangent[:, 1] * axis[0] + tangent[:, 0] * axis[1])
    out[ok] = normal_dot[ok] >= MIN_FACING_COSINE * length[ok]
    return out


def along_axis(
    fine: CorrelationGrid,
    hits: FloatArray,
    matched: Pose2D,
    predicted: Pose2D,
    axis: FloatArray,
    prediction_stddev: float,
    max_gap: float,
) -> AlongAxis:
    """Fit the position along ``axis`` (unit, map frame) of the returns of ``hits`` (robot frame)
    that face it (``facing``), on the refinement grid ``fine``: at the ``matched`` pose's position
    across the axis and yaw, about the ``predicted`` position along it, ± SEARCH_STDDEVS ·
    ``prediction_stddev`` (m) in steps of half a cell.

    The information is the facing returns' count times the curvature of their mean smear at the
    best offset (the smear is each return's likelihood under a Gaussian of the smear deviation); a
    best offset at the end of the search or on a plateau measures nothing. The correction is the
    Kalman update of the prediction: offset · I / (I + 1 / ``prediction_stddev``²).
    """
    none = AlongAxis(axis)
    c, s = np.cos(matched.yaw), np.sin(matched.yaw)
    local_axis = np.array([c * axis[0] + s * axis[1], -s * axis[0] + c * axis[1]])
    points = hits[facing(hits, local_axis, max_gap)]
    step = 0.5 * fine.resolution
    reach = max(SEARCH_STDDEVS * prediction_stddev, 2.0 * step)
    if len(points) < MIN_FACING_POINTS:
        return none
    shift = float(axis @ np.array([predicted.x - matched.x, predicted.y - matched.y]))
    base = np.array([matched.x + shift * axis[0], matched.y + shift * axis[1], matched.yaw])
    offsets = np.arange(-np.floor(reach / step), np.floor(reach / step) + 1) * step
    candidates = base + offsets[:, None] * np.array([axis[0], axis[1], 0.0])
    values = fine.mean_smear(points, candidates)
    k = int(np.argmax(values))
    if k == 0 or k == len(values) - 1 or values[k] <= 0.0:
        return none
    left, mid, right = values[k - 1], values[k], values[k + 1]
    drop = min(mid - left, mid - right)
    curvature = (left + right - 2.0 * mid) / step**2
    if drop <= 0.0 or curvature >= 0.0:
        return none
    vertex = 0.5 * (left - right) / (left + right - 2.0 * mid)  # parabola through the three, in steps
    offset, information = float(offsets[k] + vertex * step), float(len(points) * -curvature)
    weight = information / (information + prediction_stddev**-2) if prediction_stddev > 0.0 else 1.0
    return AlongAxis(axis, offset, information, weight * offset)
