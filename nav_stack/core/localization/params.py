"""AMCL parameters with nav2_amcl's names and Jazzy defaults (nav2_params.yaml == code defaults).

Why: one frozen dataclass is the single source of defaults; the amcl node declares one ROS
parameter per field. Nav2's nested ``initial_pose.{x,y,z,yaw}`` become ``initial_pose_x`` etc.
Distances in metres, angles in radians, rates in Hz, times in seconds.

One knob Nav2 does not have: ``min_ess_ratio`` (0..1), the effective sample size, as a fraction of
the particle count, that a laser update must leave; the scan likelihood is tempered to keep it (see
weighting.py). 0 applies the full likelihood to every scan.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import ClassVar

DIFFERENTIAL = "nav2_amcl::DifferentialMotionModel"
OMNI = "nav2_amcl::OmniMotionModel"
LIKELIHOOD_FIELD = "likelihood_field"
LIKELIHOOD_FIELD_PROB = "likelihood_field_prob"  # the likelihood field with beam skipping
BEAM = "beam"
LASER_MODELS = (LIKELIHOOD_FIELD, LIKELIHOOD_FIELD_PROB, BEAM)


@dataclass(frozen=True)
class AmclParams:
    """Every nav2_amcl parameter the core or the node uses."""

    # Accepted so a Nav2 file loads, never read (nav_stack.ros.common.params warns at startup).
    IGNORED: ClassVar[dict[str, str]] = {
        "save_pose_rate": "the estimate is not stored for the next run; set_initial_pose starts it",
        "initial_pose_z": "the filter is planar: a pose has no height",
    }

    alpha1: float = 0.2
    alpha2: float = 0.2
    alpha3: float = 0.2
    alpha4: float = 0.2
    alpha5: float = 0.2
    base_frame_id: str = "base_footprint"
    global_frame_id: str = "map"
    odom_frame_id: str = "odom"
    # Beam skipping, read only by likelihood_field_prob (as in Nav2; see likelihood_field_prob.py):
    beam_skip_distance: float = 0.5  # m from an obstacle within which a beam endpoint agrees with the map
    beam_skip_error_threshold: float = 0.9  # fraction of max_beams skipped at which all beams count again
    beam_skip_threshold: float = 0.3  # fraction of particles a beam must agree for to be integrated
    do_beamskip: bool = False
    lambda_short: float = 0.1
    laser_likelihood_max_dist: float = 2.0
    laser_max_range: float = 100.0
    laser_min_range: float = -1.0
    laser_model_type: str = LIKELIHOOD_FIELD
    max_beams: int = 60
    max_particles: int = 2000
    min_particles: int = 500
    pf_err: float = 0.05
    pf_z: float = 0.99
    recovery_alpha_fast: float = 0.0
    recovery_alpha_slow: float = 0.0
    resample_interval: int = 1
    robot_model_type: str = DIFFERENTIAL
    save_pose_rate: float = 0.5
    sigma_hit: float = 0.2
    tf_broadcast: bool = True
    transform_tolerance: float = 1.0
    update_min_a: float = 0.2
    update_min_d: float = 0.25
    z_hit: float = 0.5
    z_max: float = 0.05
    z_rand: float = 0.5
    z_short: float = 0.05
    min_ess_ratio: float = 0.5
    scan_topic: str = "scan"
    map_topic: str = "map"
    set_initial_pose: bool = False
    initial_pose_x: float = 0.0
    initial_pose_y: float = 0.0
    initial_pose_z: float = 0.0
    initial_pose_yaw: float = 0.0
    always_reset_initial_pose: bool = False
    first_map_only: bool = False

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                raise ValueError(f"AmclParams.{f.name} must be finite, got {value}")
        for name in ("alpha1", "alpha2", "alpha3", "alpha4", "alpha5", "z_hit", "z_rand", "z_short",
                     "z_max", "recovery_alpha_fast", "recovery_alpha_slow", "update_min_d", "update_min_a",
                     "lambda_short"):
            if getattr(self, name) < 0.0:
                raise ValueError(f"AmclParams.{name} must be >= 0, got {getattr(self, name)}")
        for name in ("sigma_hit", "laser_likelihood_max_dist", "pf_err"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"AmclParams.{name} must be > 0, got {getattr(self, name)}")
        if not 1 <= self.min_particles <= self.max_particles:
            raise ValueError(f"AmclParams needs 1 <= min_particles <= max_particles, got "
                             f"min_particles={self.min_particles}, max_particles={self.max_particles}")
        if not 0.0 <= self.min_ess_ratio < 1.0:
            raise ValueError(f"AmclParams.min_ess_ratio must be in [0, 1), got {self.min_ess_ratio}")
        if self.max_beams < 2:
            raise ValueError(f"AmclParams.max_beams must be >= 2, got {self.max_beams}")
        if self.resample_interval < 1:
            raise ValueError(f"AmclParams.resample_interval must be >= 1, got {self.resample_interval}")
        if self.laser_model_type not in LASER_MODELS:
            raise ValueError(f"AmclParams.laser_model_type must be one of {', '.join(LASER_MODELS)}, "
                             f"got {self.laser_model_type!r}")
        if self.beam_skip_distance < 0.0:
            raise ValueError(f"AmclParams.beam_skip_distance must be >= 0, got {self.beam_skip_distance}")
        for name in ("beam_skip_threshold", "beam_skip_error_threshold"):
            if not 0.0 <= getattr(self, name) <= 1.0:  # fractions (of particles, of beams)
                raise ValueError(f"AmclParams.{name} must be in [0, 1], got {getattr(self, name)}")
        if self.robot_model_type not in (DIFFERENTIAL, OMNI):
            raise ValueError(f"AmclParams.robot_model_type must be '{DIFFERENTIAL}' or '{OMNI}', "
                             f"got {self.robot_model_type!r}")
