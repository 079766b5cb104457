"""MPPI's controller-wide parameters (nav2_mppi_controller, Jazzy): names, defaults, checks.

Defaults are the values of Jazzy's own nav2_params.yaml (the TurtleBot3 configuration) wherever
that file sets the knob, else the code default, so that ``FollowPath.plugin:
nav2_mppi_controller::MPPIController`` alone behaves like Nav2's shipped MPPI. Where the code
default differs it is named in a comment. Units: m, s, m/s, rad/s, m/s², rad/s².

The critics' own parameters live in critic_params.py; ``AckermannConstraints.min_turning_r`` and
``TrajectoryVisualizer.*`` are dataclasses of their own here because Nav2 spells them under their
own sub-namespace (``FollowPath.AckermannConstraints.min_turning_r``).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from nav_stack.core.control.mppi.critic_params import CRITIC_PARAMS

#: Jazzy nav2_params.yaml's critics, in its order (the code default is none)
JAZZY_CRITICS = ("ConstraintCritic", "CostCritic", "GoalCritic", "GoalAngleCritic", "PathAlignCritic",
                 "PathFollowCritic", "PathAngleCritic", "PreferForwardCritic")
#: s: how far apart the controller period and model_dt may be and still count as equal (Nav2's eps)
PERIOD_EPS = 1e-6


class MotionModel(enum.IntEnum):
    """Nav2's ``motion_model`` names; the value is the code the compiled kernels switch on."""

    DiffDrive = 0
    Omni = 1
    Ackermann = 2

    @property
    def holonomic(self) -> bool:
        """Whether the model samples a lateral velocity vy."""
        return self is MotionModel.Omni


@dataclass(frozen=True)
class MPPIParams:
    """The controller-wide knobs under ``<plugin id>.`` (``FollowPath.batch_size``).

    ``controller_frequency`` and ``goal_dist_tol`` come from the controller server (its rate and the
    goal checker's xy tolerance, which Nav2's TwirlingCritic asks the goal checker for), not from
    parameters of their own, as for RPP.
    """

    motion_model: str = "DiffDrive"
    critics: tuple[str, ...] = JAZZY_CRITICS
    iteration_count: int = 1
    batch_size: int = 2000  # code default 1000
    time_steps: int = 56
    model_dt: float = 0.05  # s
    vx_std: float = 0.2
    vy_std: float = 0.2
    wz_std: float = 0.4
    vx_max: float = 0.5
    vx_min: float = -0.35
    vy_max: float = 0.5
    wz_max: float = 1.9
    ax_max: float = 3.0
    ax_min: float = -3.0  # a positive value is taken as its negative, as Nav2 does
    ay_max: float = 3.0
    ay_min: float = -3.0  # Omni only; like ax_min, a positive value is taken as its negative
    az_max: float = 3.5
    temperature: float = 0.3
    gamma: float = 0.015
    visualize: bool = True  # code default false
    retry_attempt_limit: int = 1
    regenerate_noises: bool = True  # code default false
    prune_distance: float = 1.7  # m of path ahead of the robot the critics see (code default 1.5)
    # s; accepted for Nav2 files, unused: the controller server does the transforms (and waits for them)
    transform_tolerance: float = 0.1
    enforce_path_inversion: bool = False
    inversion_xy_tolerance: float = 0.2  # m
    inversion_yaw_tolerance: float = 0.4  # rad
    # Not in Nav2: the seed of the sampling noise, so that runs repeat (as nav_stack's AMCL has);
    # -1 draws it from the OS (Nav2's behaviour).
    random_seed: int = 0
    controller_frequency: float = 20.0  # Hz, from the controller server
    goal_dist_tol: float = 0.25  # m, from the goal checker

    def __post_init__(self) -> None:
        if self.motion_model not in MotionModel.__members__:
            raise ValueError(f"MPPIParams.motion_model '{self.motion_model}' is not one of "
                             f"{list(MotionModel.__members__)}")
        unknown = [name for name in self.critics if name not in CRITIC_PARAMS]
        if unknown:
            raise ValueError(f"MPPIParams.critics {unknown} are not among {sorted(CRITIC_PARAMS)}")
        for name in ("iteration_count", "batch_size"):
            if getattr(self, name) < 1:
                raise ValueError(f"MPPIParams.{name} must be >= 1, got {getattr(self, name)}")
        if self.time_steps < 2:
            raise ValueError(f"MPPIParams.time_steps must be >= 2, got {self.time_steps}")
        if self.retry_attempt_limit < 0:
            raise ValueError(f"MPPIParams.retry_attempt_limit must be >= 0, got {self.retry_attempt_limit}")
        for name in ("model_dt", "temperature", "vx_std", "controller_frequency", "ax_max", "az_max"):
            value = getattr(self, name)
            if not (value > 0.0 and math.isfinite(value)):
                raise ValueError(f"MPPIParams.{name} must be > 0, got {value}")
        for name in ("vy_std", "wz_std", "gamma", "vy_max", "wz_max", "ay_max", "prune_distance"):
            if not getattr(self, name) >= 0.0:
                raise ValueError(f"MPPIParams.{name} must be >= 0, got {getattr(self, name)}")
        if self.model.holonomic and not self.vy_std > 0.0:
            raise ValueError(f"MPPIParams.vy_std must be > 0 for the Omni model, got {self.vy_std}")
        if not self.vx_min <= self.vx_max:
            raise ValueError(f"MPPIParams: vx_min {self.vx_min} > vx_max {self.vx_max}")
        if 1.0 / self.controller_frequency > self.model_dt + PERIOD_EPS:
            raise ValueError(f"MPPIParams: the controller period {1.0 / self.controller_frequency:.4f} s is "
                             f"longer than model_dt {self.model_dt} s; set model_dt to it "
                             "(Nav2 refuses this)")

    @property
    def model(self) -> MotionModel:
        """The motion model as an enum."""
        return MotionModel[self.motion_model]

    @property
    def shift_control_sequence(self) -> bool:
        """Whether each cycle shifts the control sequence by one model_dt: Nav2 does so when the
        controller period equals model_dt (a shorter period keeps the sequence as it is)."""
        return abs(1.0 / self.controller_frequency - self.model_dt) < PERIOD_EPS

    @property
    def decel_limit(self) -> float:
        """ax_min as a non-positive acceleration (m/s²), whatever sign was given."""
        return -abs(self.ax_min)

    @property
    def lateral_decel_limit(self) -> float:
        """ay_min as a non-positive acceleration (m/s²), whatever sign was given."""
        return -abs(self.ay_min)


@dataclass(frozen=True)
class AckermannConstraints:
    """``<id>.AckermannConstraints.*``: only read for ``motion_model: Ackermann``."""

    min_turning_r: float = 0.2  # m

    def __post_init__(self) -> None:
        if not self.min_turning_r >= 0.0:
            raise ValueError(f"AckermannConstraints.min_turning_r must be >= 0, got {self.min_turning_r}")


@dataclass(frozen=True)
class TrajectoryVisualizerParams:
    """``<id>.TrajectoryVisualizer.*``: which sampled trajectories, and which of their points, are drawn."""

    trajectory_step: int = 5  # every n-th trajectory of the batch
    time_step: int = 3  # every n-th point of each

    def __post_init__(self) -> None:
        if self.trajectory_step < 1 or self.time_step < 1:
            raise ValueError(f"TrajectoryVisualizer steps must be >= 1, got trajectory_step "
                             f"{self.trajectory_step}, time_step {self.time_step}")
