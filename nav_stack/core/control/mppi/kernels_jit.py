"""One MPPI iteration compiled with numba: reference.py's rollout, critics and softmax update.

Why compiled: 2000 samples × 56 steps × 8 critics is about a million pose evaluations a cycle;
numpy needs many passes over (B, T) arrays and Python loops where Nav2's semantics are sequential
(the furthest reached path point, the first collision of each trajectory), the compiled loops
touch each pose a few times. The maths is reference.py's, step for step (sums in the same order),
and tests/unit/nav_stack/test_mppi_jit.py checks that both give the same costs, trajectories and
control sequence for the same noise. No parallel threads: the stack shares two cores.

The poses' headings: cos and sin of yaw_{j} are carried along the trajectory by rotating them by
the step's angle wz·dt (a short Taylor series, |wz·dt| <= 0.25 rad, else libm), instead of two
libm calls per pose; the two agree to ~1e-15 per step.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt
from numba import njit

from nav_stack.core.control.mppi.critics_jit import score
from nav_stack.core.control.mppi.packing import context, pack
from nav_stack.core.control.mppi.params import MPPIParams
from nav_stack.core.control.mppi.scene import Rollouts, Scene

F64 = npt.NDArray[np.float64]
U8 = npt.NDArray[np.uint8]

ROTATION_SERIES_LIMIT = 0.25  # rad: |wz·dt| up to which the Taylor series is exact to ~1e-16
_C4, _C6, _C8, _C10 = 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0
_S3, _S5, _S7, _S9, _S11 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0


@njit(cache=True, error_model="numpy", inline="always")
def _bound(control: float, last: float, up: float, down: float) -> float:
    """reference.bound for one value."""
    if last > 0.0:
        return min(max(control, last - down), last + up)
    return min(max(control, last - up), last + down)


@njit(cache=True, error_model="numpy", inline="always")
def _rotation(a: float) -> tuple[float, float]:
    """(cos a, sin a): Taylor series to a^11 for small angles (error < 2e-16 below 0.25 rad), else libm.
    Horner form with constant products: divisions would make it several times slower."""
    if abs(a) > ROTATION_SERIES_LIMIT:
        return math.cos(a), math.sin(a)
    a2 = a * a
    c = 1.0 + a2 * (-0.5 + a2 * (_C4 + a2 * (_C6 + a2 * (_C8 + a2 * _C10))))
    s = a * (1.0 + a2 * (_S3 + a2 * (_S5 + a2 * (_S7 + a2 * (_S9 + a2 * _S11)))))
    return c, s


@njit(cache=True, error_model="numpy", fastmath={"contract"})
def rollout(seq: F64, noise: Any, std: F64, speed: F64, pose: F64, holo: bool, dt: float, limits: F64,
            cvx: F64, cvy: F64, cwz: F64, vx: F64, vy: F64, wz: F64, x: F64, y: F64, yaw: F64) -> None:
    """reference.rollout: ``limits`` = (ax_max·dt, |ax_min|·dt, ay_max·dt, az_max·dt, |ay_min|·dt).
    One pass per trajectory: control j is sampled, bounded by velocity j and becomes velocity j + 1; pose j
    integrates velocity j from heading j − 1. (Fused multiply-adds allowed: ~1e-16 differences.)"""
    up, down, side_up, turn, side_down = limits[0], limits[1], limits[2], limits[3], limits[4]
    steps = cvx.shape[1]
    c0, s0 = math.cos(pose[2]), math.sin(pose[2])
    u_vx, u_vy, u_wz = seq[0], seq[1], seq[2]
    for i in range(cvx.shape[0]):
        e_vx, e_vy, e_wz = noise[0, i], noise[1, i], noise[2, i]
        cvx_i, cvy_i, cwz_i, vx_i, vy_i, wz_i = cvx[i], cvy[i], cwz[i], vx[i], vy[i], wz[i]
        x_i, y_i, yaw_i = x[i], y[i], yaw[i]
        lx, ly, lw = speed[0], speed[1] if holo else 0.0, speed[2]
        heading, px, py, c, s = pose[2], pose[0], pose[1], c0, s0
        for j in range(steps):
            vx_i[j] = lx
            vy_i[j] = ly
            wz_i[j] = lw
            px += (lx * c - ly * s) * dt
            py += (lx * s + ly * c) * dt
            step = lw * dt
            heading += step
            x_i[j] = px
            y_i[j] = py
            yaw_i[j] = heading
            rc, rs = _rotation(step)
            c, s = c * rc - s * rs, s * rc + c * rs
            ux = u_vx[j] + std[0] * e_vx[j]
            uw = u_wz[j] + std[2] * e_wz[j]
            uy = u_vy[j] + std[1] * e_vy[j] if holo else 0.0
            if j + 1 < steps:
                ux = _bound(ux, lx, up, down)
                uw = min(max(uw, lw - turn), lw + turn)
                if holo:
                    uy = _bound(uy, ly, side_up, side_down)
                lx, ly, lw = ux, uy, uw
            cvx_i[j] = ux
            cvy_i[j] = uy
            cwz_i[j] = uw


@njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"})
def weigh(seq: F64, cvx: F64, cvy: F64, cwz: F64, per_critic: F64, gains: F64, temperature: float,
          total: F64, mean: F64) -> None:
    """reference.control_costs + weighted_mean: ``gains`` = γ/σ² per axis (vx, vy, wz), 0 = unsampled
    (its controls are then all 0 and skipped). Sums may be reordered (vectorised): ~1e-16 differences."""
    batch, steps = cvx.shape
    lateral = gains[1] > 0.0
    u_vx, u_vy, u_wz = seq[0], seq[1], seq[2]
    for i in range(batch):
        critic = 0.0
        for k in range(per_critic.shape[0]):
            critic += per_critic[k, i]
        cvx_i, cwz_i = cvx[i], cwz[i]
        ax, aw = 0.0, 0.0
        for t in range(steps):
            ax += (cvx_i[t] - u_vx[t]) * u_vx[t]
            aw += (cwz_i[t] - u_wz[t]) * u_wz[t]
        control = gains[0] * ax
        if gains[2] > 0.0:
            control = control + gains[2] * aw
        if lateral:
            cvy_i, ay = cvy[i], 0.0
            for t in range(steps):
                ay += (cvy_i[t] - u_vy[t]) * u_vy[t]
            control = control + gains[1] * ay
        total[i] = critic + control
    lowest = total.min()
    weights = np.exp(-(total - lowest) / temperature)
    weights /= weights.sum()
    mean[:] = 0.0
    m_vx, m_vy, m_wz = mean[0], mean[1], mean[2]
    for i in range(batch):
        w, cvx_i, cwz_i = weights[i], cvx[i], cwz[i]
        for t in range(steps):
            m_vx[t] += w * cvx_i[t]
            m_wz[t] += w * cwz_i[t]
        if lateral:
            cvy_i = cvy[i]
            for t in range(steps):
                m_vy[t] += w * cvy_i[t]


class JitKernels:
    """The compiled iteration for one parameter set (reference.ReferenceKernels' twin)."""

    def __init__(self, params: MPPIParams, critics: Sequence[tuple[str, Any]], min_turning_r: float) -> None:
        self.params, self.min_turning_r = params, min_turning_r
        self.codes, self.table = pack(critics, params)
        p = params
        self._std = np.array([p.vx_std, p.vy_std, p.wz_std])
        self._limits = np.array([p.ax_max * p.model_dt, -p.decel_limit * p.model_dt, p.ay_max * p.model_dt,
                                 p.az_max * p.model_dt, -p.lateral_decel_limit * p.model_dt])
        holo = p.model.holonomic
        self._gains = np.array([p.gamma / p.vx_std**2, p.gamma / p.vy_std**2 if holo else 0.0,
                                p.gamma / p.wz_std**2 if p.wz_std > 0.0 else 0.0])
        self._per_critic = np.zeros((len(critics), p.batch_size))
        self._total = np.zeros(p.batch_size)

    def iterate(self, sequence: F64, noise: Any, scene: Scene, out: Rollouts) -> tuple[F64, F64, bool]:
        """(new sequence (3, T), per-critic costs (C, B), every trajectory collides)."""
        p = self.params
        robot = scene.robot
        rollout(sequence, noise, self._std, np.asarray(scene.speed), np.array([robot.x, robot.y, robot.yaw]),
                p.model.holonomic, p.model_dt, self._limits, out.cvx, out.cvy, out.cwz, out.vx, out.vy,
                out.wz, out.x, out.y, out.yaw)
        fail = score(self.codes, self.table, context(scene, p, self.min_turning_r), out.x, out.y, out.yaw,
                     out.vx, out.vy, out.wz, scene.grid.costs, scene.grid_meta(), scene.footprint.outline,
                     scene.path, self._per_critic)
        mean = np.zeros_like(sequence)
        weigh(sequence, out.cvx, out.cvy, out.cwz, self._per_critic, self._gains, p.temperature, self._total,
              mean)
        return mean, self._per_critic, fail


def warm_up() -> None:
    """Compile (or load from the cache) every kernel now, the noise's and the optimizer's too, on a
    4-sample, 8-step problem."""
    from nav_stack.core.control.base import CostGrid, Twist2D
    from nav_stack.core.control.mppi import noise as sampling
    from nav_stack.core.control.mppi import sequence_jit
    from nav_stack.core.control.mppi.critic_params import CRITIC_PARAMS
    from nav_stack.core.control.mppi.scene import FootprintModel
    from nav_stack.core.geometry import Pose2D
    from nav_stack.core.grid import GridSpec

    params = MPPIParams(batch_size=4, time_steps=8, critics=tuple(CRITIC_PARAMS))
    critics = [(name, cls()) for name, cls in CRITIC_PARAMS.items()]
    grid = CostGrid(np.zeros((10, 10), dtype=np.uint8), GridSpec(10, 10, 0.1, -0.5, -0.5))
    path = np.column_stack([np.linspace(0.0, 0.4, 5), np.zeros(5), np.zeros(5)])
    for outline in (np.zeros((0, 2)), np.array([[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]])):
        footprint = FootprintModel(outline, 1.0, 0.05)
        scene = Scene.make(Pose2D(0.0, 0.0, 0.0), Twist2D(0.1, 0.0), path, path[-1], grid, footprint)
        for noise in (np.zeros((3, 4, 8), dtype=np.float32), np.zeros((3, 4, 8))):
            JitKernels(params, critics, 0.2).iterate(np.zeros((3, 8)), noise, scene, Rollouts.empty(4, 8))
    sampling.warm_up()
    sequence_jit.warm_up()
