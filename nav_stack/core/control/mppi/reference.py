"""One MPPI iteration in plain numpy: rollout, critics, softmax update. kernels_jit.py compiles the same.

Kept as the definition the compiled kernels are tested against (tests/unit/nav_stack/test_mppi_jit.py)
and as the backend of ``MPPIController(kernels="reference")``. The maths, as Nav2 Jazzy's optimizer:

* controls c = sequence + σ·ε for every sample (ε standard normal noise, (3, B, T): vx, vy, wz);
* the motion model bounds each control by the acceleration limits from the previous velocity,
  starting at the measured speed: ``v[:, 0]`` = speed, ``v[:, j]`` = clamp(``c[:, j-1]``); a forward
  speed may fall by |ax_min|·dt and rise by ax_max·dt per step (mirrored when reversing; vy likewise
  with ay_min / ay_max, wz by ±az_max·dt); the bounded value is written back into c;
* poses: yaw_j = yaw_0 + Σ_{k≤j} wz_k·dt, x_j = x_0 + Σ_{k≤j} (vx_k·cos yaw_{k-1} − vy_k·sin yaw_{k-1})·dt;
* cost = Σ critics + γ/σ² · Σ_t (c_t − u_t)·u_t per axis (the control cost of MPPI, u the sequence);
* weights softmax(−(cost − min cost)/temperature); the new sequence is the weighted mean of c.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nav_stack.core.control.mppi import critics as critic_defs
from nav_stack.core.control.mppi.params import MPPIParams
from nav_stack.core.control.mppi.scene import Rollouts, Scene
from nav_stack.core.geometry import FloatArray


def _running_sum(start: float, steps: FloatArray) -> FloatArray:
    """start + cumulative sums of ``steps`` along axis 1, added in the order a loop would."""
    column = np.full((len(steps), 1), start)
    return np.asarray(np.cumsum(np.concatenate([column, steps], axis=1), axis=1)[:, 1:])


def bound(control: FloatArray, last: FloatArray, up: float, down: float) -> FloatArray:
    """Clamp ``control`` to what ``last`` can reach in one step: +up/−down (m/s) moving forward
    (last > 0), mirrored otherwise (Nav2's predict; ``down`` >= 0 is |ax_min|·dt)."""
    lo = np.where(last > 0.0, last - down, last - up)
    hi = np.where(last > 0.0, last + up, last + down)
    return np.asarray(np.clip(control, lo, hi))


def rollout(sequence: FloatArray, noise: Any, scene: Scene, p: MPPIParams, out: Rollouts) -> Rollouts:
    """Sample controls around ``sequence`` (3, T) with ``noise`` (3, B, T), bound them, integrate poses."""
    holo = p.model.holonomic
    dt = p.model_dt
    eps = np.asarray(noise, dtype=np.float64)  # float32 noise, scaled in double precision
    out.cvx[:] = sequence[0] + p.vx_std * eps[0]
    out.cwz[:] = sequence[2] + p.wz_std * eps[2]
    out.cvy[:] = sequence[1] + p.vy_std * eps[1] if holo else 0.0
    vx0, vy0, wz0 = scene.speed
    out.vx[:, 0], out.vy[:, 0], out.wz[:, 0] = vx0, vy0 if holo else 0.0, wz0
    up, down, turn = p.ax_max * dt, -p.decel_limit * dt, p.az_max * dt
    side_up, side_down = p.ay_max * dt, -p.lateral_decel_limit * dt
    for j in range(1, sequence.shape[1]):
        out.cvx[:, j - 1] = bound(out.cvx[:, j - 1], out.vx[:, j - 1], up, down)
        out.vx[:, j] = out.cvx[:, j - 1]
        out.cwz[:, j - 1] = np.clip(out.cwz[:, j - 1], out.wz[:, j - 1] - turn, out.wz[:, j - 1] + turn)
        out.wz[:, j] = out.cwz[:, j - 1]
        if holo:
            out.cvy[:, j - 1] = bound(out.cvy[:, j - 1], out.vy[:, j - 1], side_up, side_down)
            out.vy[:, j] = out.cvy[:, j - 1]
    out.x[:], out.y[:], out.yaw[:] = poses(out.vx, out.vy, out.wz, scene.robot, dt)
    return out


def poses(vx: FloatArray, vy: FloatArray, wz: FloatArray, robot: Any, dt: float
          ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """x, y, yaw (B, T) reached from ``robot`` (Pose2D) by the velocities (B, T), each held for dt."""
    yaw = _running_sum(robot.yaw, wz * dt)
    heading = np.concatenate([np.full((len(yaw), 1), robot.yaw), yaw[:, :-1]], axis=1)
    c, s = np.cos(heading), np.sin(heading)
    return _running_sum(robot.x, (vx * c - vy * s) * dt), _running_sum(robot.y, (vx * s + vy * c) * dt), yaw


def control_costs(sequence: FloatArray, r: Rollouts, p: MPPIParams) -> FloatArray:
    """MPPI's control cost γ/σ² · Σ_t (c_t − u_t)·u_t per sample, summed over the sampled axes
    (wz only when wz_std > 0, vy only for holonomic models)."""
    total = p.gamma / p.vx_std**2 * ((r.cvx - sequence[0]) * sequence[0]).sum(axis=1)
    if p.wz_std > 0.0:
        total = total + p.gamma / p.wz_std**2 * ((r.cwz - sequence[2]) * sequence[2]).sum(axis=1)
    if p.model.holonomic:
        total = total + p.gamma / p.vy_std**2 * ((r.cvy - sequence[1]) * sequence[1]).sum(axis=1)
    return np.asarray(total)


def weighted_mean(costs: FloatArray, r: Rollouts, p: MPPIParams) -> tuple[FloatArray, FloatArray]:
    """The softmax weights of the costs and the weighted mean of the bounded controls (3, T)."""
    weights = np.exp(-(costs - costs.min()) / p.temperature)
    weights /= weights.sum()
    mean = np.stack([weights @ r.cvx, weights @ r.cvy, weights @ r.cwz])
    return weights, mean


def iterate(sequence: FloatArray, noise: Any, scene: Scene, p: MPPIParams, critics: list[tuple[str, Any]],
            min_turning_r: float, out: Rollouts) -> tuple[FloatArray, FloatArray, bool]:
    """One MPPI iteration: (new sequence (3, T), per-critic costs (C, B), every trajectory collides)."""
    rollout(sequence, noise, scene, p, out)
    per_critic, fail = critic_defs.evaluate(critics, scene, out, p, min_turning_r)
    total = per_critic.sum(axis=0) + control_costs(sequence, out, p)
    _, mean = weighted_mean(total, out, p)
    return mean, per_critic, fail


class ReferenceKernels:
    """The numpy iteration for one parameter set (kernels_jit.JitKernels' twin)."""

    def __init__(self, params: MPPIParams, critics: list[tuple[str, Any]], min_turning_r: float) -> None:
        self.params, self.critics, self.min_turning_r = params, list(critics), min_turning_r

    def iterate(self, sequence: FloatArray, noise: Any, scene: Scene, out: Rollouts
                ) -> tuple[FloatArray, FloatArray, bool]:
        """(new sequence (3, T), per-critic costs (C, B), every trajectory collides)."""
        return iterate(sequence, noise, scene, self.params, self.critics, self.min_turning_r, out)
