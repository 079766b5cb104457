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
from nav_stack.core.control.mppi import sequence_jit
from nav_stack.core.control.mppi.kernels_jit import JitKernels
from nav_stack.core.control.mppi.noise import NoiseGenerator
from nav_stack.core.control.mppi.params import MotionModel, MPPIParams
from nav_stack.core.control.mppi.reference import ReferenceKernels
from nav_stack.core.control.mppi.scene import Rollouts, Scene
from nav_stack.core.geometry import FloatArray


def savitzky_golay(sequence: FloatArray, history: FloatArray) -> None:
    """Smooth every axis of ``sequence`` (3, T) in place but its last element: each element becomes
    the quadratic 9-point Savitzky-Golay filter over itself, the four before it (the last commands,
    ``history`` (4, 3) oldest first, before the start) and the four after it (the last element
    repeated past the end). Sequences shorter than 21 steps stay as they are, as in Nav2."""
    sequence_jit.smooth(sequence, history, sequence_jit.SGF_WEIGHTS)


def constrain(sequence: FloatArray, speed: tuple[float, float, float], p: MPPIParams,
              min_turning_r: float) -> None:
    """Clamp ``sequence`` (3, T) in place to the velocity limits and, step by step from the measured
    ``speed``, to the acceleration limits (the first step over the controller period, later ones over
    model_dt; a forward speed falls by at most |ax_min|·dt and rises by ax_max·dt, mirrored when
    reversing); element 0 is the speed itself when the sequence shifts. Ackermann: |wz| <= |vx| / r."""
    limits = np.array([p.vx_min, p.vx_max, p.vy_max, p.wz_max, p.ax_max, -p.decel_limit, p.ay_max,
                       -p.lateral_decel_limit, p.az_max])
    ackermann_r = min_turning_r if p.model is MotionModel.Ackermann else 0.0
    sequence_jit.clamp(sequence, np.asarray(speed, dtype=np.float64), limits, p.model.holonomic,
                       p.shift_control_sequence, 1.0 / p.controller_frequency, p.model_dt, ackermann_r)


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
        self.history = np.zeros((sequence_jit.HISTORY, 3))
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
        robot = scene.robot
        self.optimal_trajectory = sequence_jit.drive(self.sequence, robot.x, robot.y, robot.yaw, p.model_dt)
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
