"""Clusters of particles and the pose estimate (nav2_amcl pf_cluster_stats).

Why: with several hypotheses (symmetric corridors, global localization) the weighted mean of all
particles lies between them; Nav2 reports the mean of the heaviest cluster instead. A cluster is a
connected set of occupied histogram bins (26-neighbourhood in x, y, yaw bins; the yaw bins wrap round
at ±π: bins that did not wrap split a cloud facing west in two). The covariance is the
whole set's, as Nav2 publishes it: weighted (x, y) covariance and, for yaw, the circular variance
−2·ln R with R the length of the weighted mean heading vector.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.grid import FloatArray
from nav_stack.core.localization.kld import bin_keys, decode_keys, wrap_yaw_bin

_NEIGHBOURS = [d for d in itertools.product((-1, 0, 1), repeat=3) if d != (0, 0, 0)]


@dataclass(frozen=True)
class PoseEstimate:
    """Pose (m, m, rad) of the heaviest cluster with the set's 3×3 covariance and cluster count."""

    x: float
    y: float
    yaw: float
    covariance: FloatArray
    cluster_weight: float
    cluster_count: int


def cluster_labels(particles: FloatArray) -> npt.NDArray[np.int64]:
    """Cluster id (0..C−1) of each particle: connected components of occupied bins."""
    keys = bin_keys(particles)
    ukeys, inverse = np.unique(keys, return_inverse=True)
    kx, ky, kt = decode_keys(ukeys)
    src_list, dst_list = [], []
    for dx, dy, dt in _NEIGHBOURS:
        target = ((kx + dx) << 29) | ((ky + dy) << 8) | wrap_yaw_bin(kt + dt)
        pos = np.clip(np.searchsorted(ukeys, target), 0, ukeys.size - 1)
        hit = ukeys[pos] == target
        src_list.append(np.nonzero(hit)[0])
        dst_list.append(pos[hit])
    src, dst = np.concatenate(src_list), np.concatenate(dst_list)
    labels = np.arange(ukeys.size)
    while True:
        new = labels.copy()
        np.minimum.at(new, src, labels[dst])
        new = new[new]
        if np.array_equal(new, labels):
            break
        labels = new
    _, compact = np.unique(labels, return_inverse=True)
    result: npt.NDArray[np.int64] = compact[inverse]
    return result


def estimate_pose(particles: FloatArray, weights: FloatArray) -> PoseEstimate:
    """Mean of the heaviest cluster and the whole set's covariance (weights need not be normalised)."""
    w = weights / weights.sum()
    labels = cluster_labels(particles)
    cluster_w = np.bincount(labels, weights=w)
    best = int(np.argmax(cluster_w))
    mask = labels == best
    wc = w[mask] / cluster_w[best]
    pc = particles[mask]
    x, y = float(wc @ pc[:, 0]), float(wc @ pc[:, 1])
    yaw = math.atan2(float(wc @ np.sin(pc[:, 2])), float(wc @ np.cos(pc[:, 2])))
    mean_xy = w @ particles[:, :2]
    centred = particles[:, :2] - mean_xy
    cov = np.zeros((3, 3))
    cov[:2, :2] = (centred * w[:, None]).T @ centred
    resultant = math.hypot(float(w @ np.cos(particles[:, 2])), float(w @ np.sin(particles[:, 2])))
    cov[2, 2] = -2.0 * math.log(max(resultant, 1e-12))
    return PoseEstimate(x, y, yaw, cov, float(cluster_w[best]), int(cluster_w.size))
