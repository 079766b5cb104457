"""The numbers behind a run report, on plain numpy arrays (no ROS types, no plotting).

Times are seconds of ROS time (sim time in simulation), positions metres, angles radians.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Trajectory:
    """Timed 2D poses: ``t`` (N,) s, ``xy`` (N, 2) m, ``yaw`` (N,) rad, sorted by time."""

    t: np.ndarray
    xy: np.ndarray
    yaw: np.ndarray

    def __len__(self) -> int:
        return int(self.t.shape[0])


@dataclass(frozen=True)
class Transition:
    """One state-machine transition: when, in which machine, from/to which state, tag and event."""

    t: float
    machine: str
    source: str
    target: str
    tag: str
    event: str


@dataclass(frozen=True)
class Segment:
    """A state being active from ``start`` to ``end`` (s); ``tag`` of the transition that entered it."""

    machine: str
    state: str
    start: float
    end: float
    tag: str


def make_trajectory(t: Sequence[float], xy: Sequence[Sequence[float]], yaw: Sequence[float]) -> Trajectory:
    """Build a trajectory from lists, sorted by time."""
    times = np.asarray(t, dtype=float)
    order = np.argsort(times, kind="stable")
    points = np.asarray(xy, dtype=float).reshape(-1, 2)
    return Trajectory(times[order], points[order], np.asarray(yaw, dtype=float)[order])


def localization_error(truth: Trajectory, estimate: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """Position error (m) of ``estimate`` against ``truth``, at the estimate's stamps.

    The true position is linearly interpolated at each estimate stamp; estimates outside the
    truth's time span are dropped (no extrapolation). Returns ``(t, error)``.
    """
    if len(truth) < 2 or len(estimate) == 0:
        return np.empty(0), np.empty(0)
    inside = (estimate.t >= truth.t[0]) & (estimate.t <= truth.t[-1])
    t = estimate.t[inside]
    true_x = np.interp(t, truth.t, truth.xy[:, 0])
    true_y = np.interp(t, truth.t, truth.xy[:, 1])
    error = np.hypot(estimate.xy[inside, 0] - true_x, estimate.xy[inside, 1] - true_y)
    return t, error


def state_segments(transitions: Sequence[Transition], end: float) -> list[Segment]:
    """When each state was active: a transition's target is active until the next transition.

    Transitions are grouped by machine and ordered by time; the last state of a machine lasts
    until ``end`` (s), or until its own start if that is later.
    """
    segments: list[Segment] = []
    machines = sorted({tr.machine for tr in transitions})
    for machine in machines:
        ordered = sorted((tr for tr in transitions if tr.machine == machine), key=lambda tr: tr.t)
        for current, following in zip(ordered, [*ordered[1:], None], strict=True):
            stop = following.t if following is not None else max(end, current.t)
            segments.append(Segment(machine, current.target, current.t, stop, current.tag))
    return segments


def distinct_points(points: np.ndarray, tolerance: float) -> np.ndarray:
    """Rows of ``points`` (N, k ≥ 2; x and y first) without those within ``tolerance`` (m) of an
    earlier kept row, e.g. the same goal's plan end repeated by every replanning."""
    rows = np.asarray(points, dtype=float)
    if rows.ndim != 2 or rows.shape[0] == 0:
        return rows
    kept = [rows[0]]
    for row in rows[1:]:
        if min(float(np.hypot(*(row[:2] - other[:2]))) for other in kept) > tolerance:
            kept.append(row)
    return np.stack(kept)
