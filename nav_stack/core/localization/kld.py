"""KLD-sampling particle count and the pose histogram bins it counts (nav2_amcl pf.c / pf_kdtree.c).

Why: a tight particle cloud needs far fewer particles than a spread one. Fox's KLD bound gives the
number n of samples such that, with probability pf_z, the K-L divergence between the sampled and the
true posterior stays below pf_err, given k occupied histogram bins (0.5 m × 0.5 m × 10°):
n = ⌈(k − 1)/(2·pf_err) · (1 − 2/(9(k − 1)) + √(2/(9(k − 1)))·pf_z)³⌉, clamped to
[min_particles, max_particles] (k ≤ 1 → max_particles). As in Nav2, pf_z is used directly as the
normal quantile. Nav2 draws samples one at a time until n exceeds the bound for the bins seen so
far; :func:`kld_sample_count` computes that stopping point for a whole draw at once.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nav_stack.core.grid import FloatArray

BIN_XY = 0.5  # m
BIN_YAW = math.radians(10.0)  # rad
_OFFSET = 1 << 20
_YAW_OFFSET = 64  # keeps the yaw bin index of a heading in [−π, π) positive within its 8 bits
#: The yaw bin indices of headings in [−π, π): the first, and how many there are.
_YAW_FIRST = math.floor(-math.pi / BIN_YAW) + _YAW_OFFSET
_YAW_COUNT = math.floor(math.nextafter(math.pi, 0.0) / BIN_YAW) + _YAW_OFFSET - _YAW_FIRST + 1


def bin_keys(particles: FloatArray) -> npt.NDArray[np.int64]:
    """One int64 key per particle naming its (x, y, yaw) histogram bin."""
    kx = np.floor(particles[:, 0] / BIN_XY).astype(np.int64) + _OFFSET
    ky = np.floor(particles[:, 1] / BIN_XY).astype(np.int64) + _OFFSET
    kt = np.floor(particles[:, 2] / BIN_YAW).astype(np.int64) + _YAW_OFFSET
    keys: npt.NDArray[np.int64] = (kx << 29) | (ky << 8) | kt
    return keys


def decode_keys(keys: npt.NDArray[np.int64]) -> tuple[npt.NDArray[np.int64], ...]:
    """Bin indices (kx, ky, kyaw) of keys made by :func:`bin_keys` (offsets kept)."""
    return keys >> 29, (keys >> 8) & ((1 << 21) - 1), keys & 0xFF


def wrap_yaw_bin(kt: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """Yaw bin indices taken round the circle: one past the bin just under +π is the bin at −π, so
    that the two count as neighbours (a heading of 179° is 2° from one of −179°)."""
    wrapped: npt.NDArray[np.int64] = (kt - _YAW_FIRST) % _YAW_COUNT + _YAW_FIRST
    return wrapped


def kld_limit(
    k: npt.ArrayLike, pf_err: float, pf_z: float, min_particles: int, max_particles: int
) -> npt.NDArray[np.int64]:
    """Particle count bound for ``k`` occupied bins (vectorised over k)."""
    k_arr = np.asarray(k, dtype=np.float64)
    km1 = np.maximum(k_arr - 1.0, 1.0)
    b = 2.0 / (9.0 * km1)
    x = 1.0 - b + np.sqrt(b) * pf_z
    n = np.ceil(km1 / (2.0 * pf_err) * x**3)
    n = np.where(k_arr <= 1, max_particles, np.clip(n, min_particles, max_particles))
    return n.astype(np.int64)


def kld_sample_count(keys: npt.NDArray[np.int64], pf_err: float, pf_z: float, min_particles: int,
                     max_particles: int) -> int:
    """How many of the samples (in draw order, bins ``keys``) Nav2's KLD loop keeps."""
    if keys.size == 0:
        return min_particles
    _, first = np.unique(keys, return_index=True)
    is_new = np.zeros(keys.size, dtype=np.int64)
    is_new[first] = 1
    bins_seen = np.cumsum(is_new)
    drawn = np.arange(1, keys.size + 1)
    over = drawn > kld_limit(bins_seen, pf_err, pf_z, min_particles, max_particles)
    return int(np.argmax(over)) + 1 if over.any() else int(keys.size)
