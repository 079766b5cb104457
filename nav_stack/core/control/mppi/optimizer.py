"""MPPI's optimizer (Nav2 Jazzy's mppi::Optimizer): the control sequence kept from cycle to cycle,
the noise, the iterations and the fallback when every trajectory collides.

A cycle (``eval_control``): ``iteration_count`` times sample, roll out, score and replace the
sequence by the softmax-weighted mean of the samples (kernels_jit or reference); then smooth it with
Nav2's 9-point Savitzky-Golay filter (the last four commands sent pad its start), clamp it to the
limits, send its element 1 (element 0 when the controller runs faster than model_dt) and shift it
one step. When an obstacle critic finds every trajectory colliding, the optimizer resets (zero
sequence, fresh noise) and tries again, up to ``retry_attempt_limit`` times, then raises
NoValidControl as Nav2 does.

One difference from Jazzy, taken from later Nav2: the filter runs before the clamps (Jazzy
filters after them, so its command could leave the limits slightly), and the clamps start from the
measured speed, with element 0 pinned to it when shifting, so the command sent is always within one
step of acceleration of the robot's speed (Jazzy's could be two steps away: element 1 is bounded by
element 0, which is bounded by the speed).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from nav_stack.core.control.base import NoValidControl
from nav_stack.core.control.mppi.kernels_jit import JitKernels
from nav_stack.core.control.mppi.noise import NoiseGenerator
from nav_stack.core.control.mppi.params import MotionModel, MPPIParams
from nav_stack.core.control.mppi.reference import ReferenceKernels, integrate
from nav_stack.core.control.mppi.scene import Rollouts, Scene
from nav_stack.core.geometry import FloatArray

#: Savitzky-Golay, quadratic, 9 points
SGF_WEIGHTS = np.array([-21.0, 14.0, 39.0, 54.0, 59.0, 54.0, 39.0, 14.0, -21.0]) / 231.0
SGF_MIN_STEPS = 21  # Nav2 leaves shorter sequences unfiltered
HISTORY = 4  # commands kept to pad the filter's start


def savitzky_golay(sequence: FloatArray, history: FloatArray) -> None:
    """Smooth every axis of ``sequence`` (3, T) in place but its last element: each element becomes
    the filter over itself, the four before it (the last commands, ``history`` (4, 3) oldest first,
    before the start) and the four after it (the last element repeated past the end)."""
    steps = sequence.shape[1]
    if steps < SGF_MIN_STEPS:
        return
    for axis in range(3):
        padded = np.concatenate([history[:, axis], sequence[axis], np.full(HISTORY, sequence[axis, -1])])
        sequence[axis, : steps - 1] = np.convolve(padded, SGF_WEIGHTS[::-1], mode="valid")[: steps - 1]


def constrain(sequence: FloatArray, speed: tuple[float, float, float], p: MPPIParams,
              min_turning_r: float) -> None:
    """Clamp ``sequence`` (3, T) in place to the velocity limits and, step by step from the measured
    ``speed``, to the acceleration limits (the first step over the controller period, later ones over
    model_dt); element 0 is the speed itself when the sequence shifts. Ackermann: |wz| <= |vx| / r.
    (Plain floats: a Python loop over numpy elements took a third of a millisecond.)"""
    holo = p.model.holonomic
    vx_s, vy_s, wz_s = (row.tolist() for row in sequence)
    last_x, last_y, last_w = speed[0], speed[1] if holo else 0.0, speed[2]
    if p.shift_control_sequence:
        vx_s[0], vy_s[0], wz_s[0] = last_x, last_y, last_w
    down_rate, side_down_rate, first_dt = -p.decel_limit, -p.lateral_decel_limit, 1.0 / p.controller_frequency
    for i in range(len(vx_s)):
        dt = first_dt if i == 0 else p.model_dt
        up, down, turn = p.ax_max * dt, down_rate * dt, p.az_max * dt
        vx = min(max(vx_s[i], p.vx_min), p.vx_max)
        lo, hi = (last_x - down, last_x + up) if last_x > 0.0 else (last_x - up, last_x + down)
        last_x = vx_s[i] = min(max(vx, lo), hi)
        wz = min(max(wz_s[i], -p.wz_max), p.wz_max)
        last_w = wz_s[i] = min(max(wz, last_w - turn), last_w + turn)
        if holo:
            vy = min(max(vy_s[i], -p.vy_max), p.vy_max)
            side_up, side_down = p.ay_max * dt, side_down_rate * dt
            lo, hi = (last_y - side_down, last_y + side_up) if last_y > 0.0 else (last_y - side_up,
                                                                                  last_y + side_down)
            last_y = vy_s[i] = min(max(vy, lo), hi)
    sequence[:] = (vx_s, vy_s, wz_s)
    if p.model is MotionModel.Ackermann and min_turning_r > 0.0:
        reach = np.abs(sequence[0]) / min_turning_r
        sequence[2] = np.clip(sequence[2], -reach, reach)


class Optimizer:
    """The state MPPI keeps between cycles and the loop that updates it.

    ``kernels``: "jit" (compiled, the default) or "reference" (numpy). After a cycle, ``rollouts``
    holds the sampled batch, ``costs`` the per-critic costs (C, B) and ``optimal_trajectory`` the poses
    (T, 3) the smoothed sequence drives from the robot.
    """

    def __init__(self, params: MPPIParams, critics: Sequence[tuple[str, Any]], min_turning_r: float,
                 rng: np.random.Generator, kernels: str = "jit") -> None:
        if kernels not in ("jit", "reference"):
            raise ValueError(f"kernels must be 'jit' or 'reference', got {kernels!r}")
        self.params, self.min_turning_r, self.rng = params, min_turning_r, rng
        backend = JitKernels if kernels == "jit" else ReferenceKernels
        self.kernels = backend(params, list(critics), min_turning_r)
        self.noise = NoiseGenerator(rng, params.batch_size, params.time_steps, params.model.holonomic,
                                    fast=kernels == "jit")
        self.rollouts = Rollouts.empty(params.batch_size, params.time_steps)
        self.costs = np.zeros((len(critics), params.batch_size))
        self.optimal_trajectory = np.zeros((0, 3))
        self.reset()

    def reset(self) -> None:
        """Zero sequence and command history, fresh noise (Nav2's Optimizer::reset)."""
        self.sequence = np.zeros((3, self.params.time_steps))
        self.history = np.zeros((HISTORY, 3))
        self.noise.regenerate()

    def eval_control(self, scene: Scene) -> tuple[float, float, float]:
        """This cycle's command (vx m/s, vy m/s, wz rad/s); NoValidControl when every trajectory keeps
        colliding through ``retry_attempt_limit`` resets."""
        p = self.params
        failures = 0
        while self._optimize(scene):
            failures += 1
            self.reset()
            if failures > p.retry_attempt_limit:
                raise NoValidControl(f"every one of the {p.batch_size} sampled trajectories collides "
                                     f"(after {p.retry_attempt_limit} retries)")
        offset = 1 if p.shift_control_sequence else 0
        command = tuple(float(v) for v in self.sequence[:, offset])
        self.history = np.vstack([self.history[1:], command])
        self.optimal_trajectory = integrate(self.sequence, scene.robot, p.model_dt)
        if p.shift_control_sequence:
            self.sequence[:, :-1] = self.sequence[:, 1:].copy()
        return command[0], command[1], command[2]

    def _optimize(self, scene: Scene) -> bool:
        """``iteration_count`` updates of the sequence; whether every trajectory collided in the last."""
        fail = False
        for _ in range(self.params.iteration_count):
            mean, self.costs, fail = self.kernels.iterate(self.sequence, self.noise.noise, scene,
                                                          self.rollouts)
            if self.params.regenerate_noises:
                self.noise.regenerate()
            savitzky_golay(mean, self.history)
            constrain(mean, scene.speed, self.params, self.min_turning_r)
            self.sequence = mean
        return fail
