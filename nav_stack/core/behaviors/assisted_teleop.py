"""AssistedTeleop (nav2_behaviors, Jazzy): forward an operator's commands, slowed where they would collide.

Each cycle the last teleop command is projected ahead from the robot pose, one
``simulation_time_step`` at a time while the projected time stays below ``projection_time`` (Nav2's
loop, float steps included), each pose advanced by the command with the heading it had at the start of
the step (a sideways speed turns with the robot; Nav2's projection subtracts it instead, a sign slip
that only holonomic robots would see). The robot footprint is placed at each projected pose on the
local costmap. When the pose after the k-th step (at time t_k) collides, the command is scaled by
t_k / projection_time, so the robot slows as the obstacle nears; when the very first step collides,
the command becomes zero. With no costmap yet every command becomes zero, as Nav2's collision checker
answers "not free" without one.

The goal ends with success when the operator says so (``preempt``, a message on ``preempt_teleop``)
and with TIMEOUT once ``time_allowance`` (s) has passed; an allowance of 0 or less means no limit.
The teleop command outlives a goal until it ends (:meth:`AssistedTeleop.finish` zeroes it), so a
command sent just before the goal starts is used, as in Nav2.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from nav_stack.core.behaviors.base import BehaviorResult
from nav_stack.core.control.base import CircleFootprint, CostGrid, Footprint
from nav_stack.core.geometry import FloatArray, Pose2D


class AssistedTeleopErrorCode(enum.IntEnum):
    """nav2_msgs/action/AssistedTeleop result codes (Jazzy)."""

    NONE = 0
    UNKNOWN = 730
    TIMEOUT = 731
    TF_ERROR = 732


@dataclass(frozen=True)
class AssistedTeleopParams:
    """behavior_server parameters of AssistedTeleop (Jazzy defaults; node-level names, as Nav2's)."""

    projection_time: float = 1.0  # s of commanded motion checked ahead
    simulation_time_step: float = 0.1  # s between checked poses

    def __post_init__(self) -> None:
        if not (self.projection_time > 0.0 and self.simulation_time_step > 0.0):
            raise ValueError("AssistedTeleop needs projection_time > 0 and simulation_time_step > 0, got "
                             f"{self.projection_time} and {self.simulation_time_step}")


class TeleopCommand(NamedTuple):
    """A teleop velocity: forward and sideways speed (m/s, robot frame) and yaw rate (rad/s)."""

    vx: float
    vy: float
    wz: float

    def scaled(self, factor: float) -> TeleopCommand:
        return TeleopCommand(self.vx * factor, self.vy * factor, self.wz * factor)


STOP = TeleopCommand(0.0, 0.0, 0.0)


def projection_times(params: AssistedTeleopParams) -> list[float]:
    """The times (s) after which the projected pose is checked: dt, 2·dt, ... while below
    projection_time, summed in floats as Nav2's loop does (0.1 added ten times stays below 1.0)."""
    times, t = [], params.simulation_time_step
    while t < params.projection_time:
        times.append(t)
        t += params.simulation_time_step
    return times


def projected_poses(pose: Pose2D, cmd: TeleopCommand, dt: float, steps: int) -> FloatArray:
    """(steps, 3) poses after 1..steps Euler steps of ``dt`` s of ``cmd`` from ``pose``."""
    yaw_before = pose.yaw + cmd.wz * dt * np.arange(steps)  # heading at the start of each step
    dx = dt * (cmd.vx * np.cos(yaw_before) - cmd.vy * np.sin(yaw_before))
    dy = dt * (cmd.vx * np.sin(yaw_before) + cmd.vy * np.cos(yaw_before))
    return np.column_stack([pose.x + np.cumsum(dx), pose.y + np.cumsum(dy), yaw_before + cmd.wz * dt])


def teleop_scale(pose: Pose2D, cmd: TeleopCommand, grid: CostGrid | None, footprint: Footprint,
                 params: AssistedTeleopParams) -> float:
    """The factor (0..1) for ``cmd``: 1 when the projected motion is free, t_k / projection_time when
    the pose at t_k is the first in collision, 0 when the first one is (or there is no costmap)."""
    if grid is None:
        return 0.0
    times = projection_times(params)
    if not times:
        return 1.0
    poses = projected_poses(pose, cmd, params.simulation_time_step, len(times))
    hits = footprint.collides(footprint.cost(grid, poses[:, 0], poses[:, 1], poses[:, 2]))
    if not hits.any():
        return 1.0
    first = int(np.argmax(hits))
    return 0.0 if first == 0 else times[first] / params.projection_time


class AssistedTeleop:
    """``start`` a goal, feed ``teleop``/``preempt`` from the topics, each cycle ``check`` for an end
    then ``command`` for the velocity to publish; ``finish`` when the goal ends however it ends."""

    def __init__(self, params: AssistedTeleopParams | None = None) -> None:
        self.params = params or AssistedTeleopParams()
        self.footprint: Footprint = CircleFootprint()
        self.teleop_command = STOP
        self.current_teleop_duration = 0.0  # feedback (s)
        self.scale = 1.0  # the factor of the last command (for logs and tests)
        self._preempted = False
        self._start_time = 0.0
        self._time_allowance = 0.0

    def teleop(self, cmd: TeleopCommand) -> None:
        """The operator's latest command (kept until the next one or the end of the goal)."""
        self.teleop_command = cmd

    def preempt(self) -> None:
        """The operator is done: the running goal succeeds at the next cycle."""
        self._preempted = True

    def start(self, time_allowance: float, now: float, footprint: Footprint | None = None) -> None:
        self._preempted = False
        self._start_time, self.current_teleop_duration = now, 0.0
        self._time_allowance = time_allowance if math.isfinite(time_allowance) else 0.0
        self.footprint = footprint or CircleFootprint()

    def check(self, now: float) -> BehaviorResult | None:
        """The goal's end at ``now`` (s): TIMEOUT, success on preempt, else None (Nav2's order)."""
        elapsed = self.current_teleop_duration = now - self._start_time
        if self._time_allowance > 0.0 and elapsed > self._time_allowance:
            allowance = f"{self._time_allowance:.2f} s"
            return BehaviorResult(AssistedTeleopErrorCode.TIMEOUT,
                                  f"assisted_teleop ran out of its {allowance} time allowance", elapsed)
        if self._preempted:
            return BehaviorResult(AssistedTeleopErrorCode.NONE, "", elapsed)
        return None

    def command(self, pose: Pose2D, grid: CostGrid | None) -> TeleopCommand:
        """The teleop command, scaled so its projected motion stays collision free."""
        self.scale = teleop_scale(pose, self.teleop_command, grid, self.footprint, self.params)
        return self.teleop_command.scaled(self.scale)

    def finish(self) -> None:
        """Forget the teleop command and any preempt (Nav2's onActionCompletion)."""
        self.teleop_command = STOP
        self._preempted = False
