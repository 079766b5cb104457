"""What the optimizer does to the control sequence after each update, compiled with numba: Nav2's
Savitzky-Golay smoothing, the velocity and acceleration clamps, and the poses the sequence drives.

Why compiled: these are short loops over 56 steps × 3 axes, but run as numpy calls and a Python loop
they took about 0.35 ms a cycle (about a sixth of the compiled cycle), nearly all interpreter overhead.
No fast-math: the clamps and the integration are the Python loops' and reference.poses' arithmetic,
operation for operation; the filter's sums may round differently from np.convolve's in the last bit.
optimizer.py says what each step means and why.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from numba import njit

F64 = npt.NDArray[np.float64]

#: Savitzky-Golay, quadratic, 9 points
SGF_WEIGHTS = np.array([-21.0, 14.0, 39.0, 54.0, 59.0, 54.0, 39.0, 14.0, -21.0]) / 231.0
SGF_MIN_STEPS = 21  # Nav2 leaves shorter sequences unfiltered
HISTORY = 4  # commands kept to pad the filter's start


@njit(cache=True, error_model="numpy")
def smooth(sequence: F64, history: F64, weights: F64) -> None:
    """Filter every axis of ``sequence`` (3, T) in place but its last element: element i becomes
    Σ_k weights[k] · padded[i + k], where padded is the last commands ``history`` (4, 3, oldest
    first), then the sequence, then its last element four more times."""
    steps = sequence.shape[1]
    if steps < SGF_MIN_STEPS:
        return
    padded = np.empty(steps + 2 * HISTORY)
    for axis in range(3):
        for k in range(HISTORY):
            padded[k] = history[k, axis]
            padded[HISTORY + steps + k] = sequence[axis, steps - 1]
        for t in range(steps):
            padded[HISTORY + t] = sequence[axis, t]
        for t in range(steps - 1):
            total = 0.0
            for k in range(weights.shape[0]):
                total += padded[t + k] * weights[k]
            sequence[axis, t] = total


@njit(cache=True, error_model="numpy")
def clamp(sequence: F64, speed: F64, limits: F64, holonomic: bool, shift: bool, first_dt: float,
          model_dt: float, min_turning_r: float) -> None:
    """optimizer.constrain on arrays: ``limits`` = (vx_min, vx_max, vy_max, wz_max, ax_max, |ax_min|,
    ay_max, |ay_min|, az_max); ``min_turning_r`` > 0 only for the Ackermann model."""
    vx_min, vx_max, vy_max, wz_max = limits[0], limits[1], limits[2], limits[3]
    ax_max, ax_down, ay_max, ay_down, az_max = limits[4], limits[5], limits[6], limits[7], limits[8]
    last_x, last_y, last_w = speed[0], speed[1] if holonomic else 0.0, speed[2]
    if shift:
        sequence[0, 0], sequence[1, 0], sequence[2, 0] = last_x, last_y, last_w
    for i in range(sequence.shape[1]):
        dt = first_dt if i == 0 else model_dt
        up, down, turn = ax_max * dt, ax_down * dt, az_max * dt
        vx = min(max(sequence[0, i], vx_min), vx_max)
        lo, hi = (last_x - down, last_x + up) if last_x > 0.0 else (last_x - up, last_x + down)
        last_x = sequence[0, i] = min(max(vx, lo), hi)
        wz = min(max(sequence[2, i], -wz_max), wz_max)
        last_w = sequence[2, i] = min(max(wz, last_w - turn), last_w + turn)
        if holonomic:
            vy = min(max(sequence[1, i], -vy_max), vy_max)
            side_up, side_down = ay_max * dt, ay_down * dt
            lo, hi = (last_y - side_down, last_y + side_up) if last_y > 0.0 else (last_y - side_up,
                                                                                  last_y + side_down)
            last_y = sequence[1, i] = min(max(vy, lo), hi)
    if min_turning_r > 0.0:
        for i in range(sequence.shape[1]):
            reach = abs(sequence[0, i]) / min_turning_r
            sequence[2, i] = min(max(sequence[2, i], -reach), reach)


@njit(cache=True, error_model="numpy")
def drive(sequence: F64, x: float, y: float, yaw: float, dt: float) -> F64:
    """The poses (T, 3) the sequence (3, T) drives from (x, y, yaw), integrated as the rollouts are
    (reference.poses: pose j uses velocity j from heading j − 1; Nav2's getOptimizedTrajectory)."""
    steps = sequence.shape[1]
    out = np.empty((steps, 3))
    heading = yaw
    for j in range(steps):
        c, s = math.cos(heading), math.sin(heading)
        vx, vy = sequence[0, j], sequence[1, j]
        x += (vx * c - vy * s) * dt
        y += (vx * s + vy * c) * dt
        heading += sequence[2, j] * dt
        out[j, 0], out[j, 1], out[j, 2] = x, y, heading
    return out


def warm_up() -> None:
    """Compile (or load from the cache) these kernels now."""
    sequence = np.zeros((3, SGF_MIN_STEPS))
    smooth(sequence, np.zeros((HISTORY, 3)), SGF_WEIGHTS)
    clamp(sequence, np.zeros(3), np.ones(9), True, True, 0.05, 0.05, 0.2)
    drive(sequence, 0.0, 0.0, 0.0, 0.05)
