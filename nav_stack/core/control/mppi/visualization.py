"""What Nav2 Jazzy's mppi::TrajectoryVisualizer draws, as arrays (the ROS layer makes the messages).

Sphere markers in the costmap frame, ids counted from 0 across both namespaces:
"Candidate Trajectories": every ``trajectory_step``-th sample, every ``time_step``-th pose of it,
0.03 m spheres at z 0.03, coloured from blue (first pose) to green (last);
"Optimal Trajectory": every pose of the optimal trajectory at z 0.06, 0.03 × 0.03 × 0.07 m (the
last 0.07 × 0.07 × 0.09 m), from black to cyan along it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nav_stack.core.geometry import FloatArray

CANDIDATES = "Candidate Trajectories"
OPTIMAL = "Optimal Trajectory"


@dataclass(frozen=True)
class MarkerSet:
    """Spheres of one namespace: ids (K,), centres (K, 3) m, sizes (K, 3) m, colours (K, 4) RGBA 0..1."""

    namespace: str
    ids: np.ndarray
    centres: FloatArray
    sizes: FloatArray
    colours: FloatArray


def candidate_markers(x: FloatArray, y: FloatArray, trajectory_step: int, time_step: int,
                      first_id: int = 0) -> MarkerSet:
    """The thinned samples of a batch (x, y: (B, T))."""
    batch, steps = x.shape
    rows, cols = np.arange(0, batch, trajectory_step), np.arange(0, steps, time_step)
    n = len(rows) * len(cols)
    grid = np.ix_(rows, cols)
    centres = np.column_stack([x[grid].ravel(), y[grid].ravel(), np.full(n, 0.03)])
    along = np.tile(cols / steps, len(rows))
    colours = np.column_stack([np.zeros(n), along, 1.0 - along, np.ones(n)])
    return MarkerSet(CANDIDATES, np.arange(first_id, first_id + n), centres, np.full((n, 3), 0.03), colours)


def optimal_markers(trajectory: FloatArray, first_id: int = 0) -> MarkerSet:
    """The optimal trajectory (T, 3)."""
    n = len(trajectory)
    centres = np.column_stack([trajectory[:, 0], trajectory[:, 1], np.full(n, 0.06)])
    sizes = np.tile([0.03, 0.03, 0.07], (n, 1))
    if n:
        sizes[-1] = (0.07, 0.07, 0.09)
    shade = np.arange(n) / max(n, 1)
    colours = np.column_stack([np.zeros(n), shade, shade, np.ones(n)])
    return MarkerSet(OPTIMAL, np.arange(first_id, first_id + n), centres, sizes, colours)


def trajectory_markers(x: FloatArray, y: FloatArray, optimal: FloatArray, trajectory_step: int,
                       time_step: int) -> list[MarkerSet]:
    """Both namespaces in Nav2's order: the candidates, then the optimal trajectory."""
    candidates = candidate_markers(x, y, trajectory_step, time_step)
    return [candidates, optimal_markers(optimal, len(candidates.ids))]
