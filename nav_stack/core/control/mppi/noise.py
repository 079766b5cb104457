"""MPPI's sampling noise: standard normal ε (3, B, T) for vx, vy, wz from the injected generator.

Nav2 draws N(0, σ²) noise on reset and, with ``regenerate_noises``, again after every use (in a
thread of its own). Here ε is standard normal and the rollout scales it by σ. Where the bits come
from: the injected, seeded ``np.random.Generator`` (its bit generator's raw 64-bit words), so a run
repeats for a given ``random_seed``.

Why a ziggurat of our own: numpy's ``standard_normal`` takes about 13 ns a sample on this machine,
3 ms for the 2 × 2000 × 56 samples of a cycle, more than the compiled critics. Marsaglia and Tsang's
ziggurat (128 layers, float32 resolution: 7 bits of layer, 1 of sign, 24 of position per 32-bit half
word) turns each half word into a sample, about 97% of the time without further bits; the rest draw
53-bit uniforms from the same stream. Where the bits come from: a SplitMix64 stream (Steele, Lea and
Flood; 64-bit words, passes BigCrush) generated inside the compiled loop, seeded with one raw word of
the injected, seeded ``np.random.Generator`` per fill, so a run repeats for a given ``random_seed``;
fetching every word from numpy's generator instead cost 0.2 ms a fill, a fifth of the noise's time.
The numpy reference backend draws with ``standard_normal`` instead (same distribution, other numbers).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from numba import njit

LAYERS = 128
TAIL = 3.442619855899  # r: where the base strip's tail starts (Marsaglia and Tsang's 128-layer table)
AREA = 9.91256303526217e-3  # v: the area of every layer
POSITION_BITS = 24


def _tables() -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(k: accept below, w: position scale, f: density) per layer. Layer i spans x in [0, x_i) at
    heights f(x_i)..f(x_{i+1}); x_0 = v/f(r) stands for the base strip with its tail."""
    x = np.zeros(LAYERS + 1)
    x[0], x[1] = AREA / math.exp(-0.5 * TAIL * TAIL), TAIL
    for i in range(1, LAYERS - 1):
        x[i + 1] = math.sqrt(-2.0 * math.log(AREA / x[i] + math.exp(-0.5 * x[i] * x[i])))
    scale = float(1 << POSITION_BITS)
    k = np.floor(x[1:] / x[:-1] * scale).astype(np.int64)
    return k, x[:-1] / scale, np.exp(-0.5 * x * x)


_K, _W, _F = _tables()


GOLDEN = np.uint64(0x9E3779B97F4A7C15)  # SplitMix64's increment and its two mixing multipliers
MIX1, MIX2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)


@njit(cache=True, error_model="numpy", inline="always")
def _next(state: np.uint64) -> tuple[np.uint64, np.uint64]:
    """SplitMix64: (the next state, its 64-bit output word)."""
    state = state + GOLDEN
    z = (state ^ (state >> np.uint64(30))) * MIX1
    z = (z ^ (z >> np.uint64(27))) * MIX2
    return state, z ^ (z >> np.uint64(31))


@njit(cache=True, error_model="numpy", inline="always")
def _uniform(word: np.uint64) -> float:
    """A uniform in (0, 1) from the top 53 bits of a word."""
    return float(((word >> np.uint64(11)) + 0.5) * (1.0 / 9007199254740992.0))


@njit(cache=True, error_model="numpy", nogil=True)
def _fill(state: np.uint64, k: npt.NDArray[np.int64], w: npt.NDArray[np.float64], f: npt.NDArray[np.float64],
          out: npt.NDArray[np.float32]) -> np.uint64:
    """Standard normals into ``out`` (flat), two per word of the SplitMix64 stream from ``state``;
    returns the stream's state after the last word used."""
    low, layer_mask, one = np.uint64(0xFFFFFFFF), np.uint64(LAYERS - 1), np.uint64(1)
    word = np.uint64(0)
    for n in range(out.shape[0]):
        if n & 1 == 0:
            state, word = _next(state)
            bits = word & low
        else:
            bits = word >> np.uint64(32)
        while True:
            i = np.int64(bits & layer_mask)
            negative = (bits >> np.uint64(7)) & one
            position = np.int64(bits >> np.uint64(8))
            if position < k[i]:
                z = position * w[i]
                break
            if i == 0:  # the tail beyond r, by Marsaglia's exponential method
                while True:
                    state, u = _next(state)
                    state, v = _next(state)
                    a = -math.log(_uniform(u)) / TAIL
                    if -2.0 * math.log(_uniform(v)) > a * a:
                        break
                z = TAIL + a
                break
            z = position * w[i]
            state, u = _next(state)
            if f[i] + _uniform(u) * (f[i + 1] - f[i]) < math.exp(-0.5 * z * z):
                break
            state, fresh = _next(state)  # rejected in the wedge: start again with fresh bits
            bits = fresh & low
        out[n] = -z if negative else z
    return state


def standard_normal_fast(rng: np.random.Generator, out: npt.NDArray[np.float32]) -> None:
    """Fill ``out`` (contiguous float32) with standard normals from a stream seeded by ``rng``."""
    _fill(np.uint64(rng.bit_generator.random_raw()), _K, _W, _F, out.reshape(-1))


class NoiseGenerator:
    """ε for the vx, vy and wz of every sample; ``noise`` is (3, B, T) float32 (vy stays 0 unless
    ``holonomic``). ``fast``: the compiled ziggurat, else numpy's standard_normal."""

    def __init__(self, rng: np.random.Generator, batch: int, steps: int, holonomic: bool,
                 fast: bool = True) -> None:
        self.rng, self.holonomic, self.fast = rng, holonomic, fast
        self.noise = np.zeros((3, batch, steps), dtype=np.float32)
        self.regenerate()

    def regenerate(self) -> None:
        """Draw new noise for the sampled axes."""
        for axis in (0, 1, 2) if self.holonomic else (0, 2):
            if self.fast:
                standard_normal_fast(self.rng, self.noise[axis])
            else:
                self.noise[axis] = self.rng.standard_normal(self.noise.shape[1:], dtype=np.float32)


def warm_up() -> None:
    """Compile (or load from the cache) the ziggurat now."""
    standard_normal_fast(np.random.default_rng(0), np.zeros(16, dtype=np.float32))
