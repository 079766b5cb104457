"""Localization health: can the AMCL estimate be trusted? (not in nav2_amcl, which never says).

Why: a particle filter does not notice that it is lost. Where the lidar sees few walls (open
space, a 3.5 m lidar in a 30 m hall) the laser update has almost nothing to weigh, the cloud only
follows odometry and spreads, and the estimate drifts silently; the navigator then fails later
with controller errors that do not name the cause. After every filter update this module looks
at the numbers that tell, and names the ones that are bad:

* returns: how many of the beams AMCL kept came back within range_max (m); in open space few do;
* agreement: of those returns, the share that ends within ``match_distance`` (m) of a wall of the
  map when cast from the estimate; a wrong estimate puts endpoints in free space. Judged only
  when there are enough returns, since two or three beams say nothing either way;
* spread: the particle cloud's position σ (m, along its widest axis) and yaw σ (rad).

A single bad update is ordinary (a person in front of the lidar, a doorway), so the state has
hysteresis: DEGRADED after ``bad_updates_to_degrade`` consecutive bad updates, OK again after
``good_updates_to_recover`` consecutive good ones (an update comes every update_min_d = 0.25 m or
update_min_a = 0.2 rad of motion, so 5 updates are about 1.25 m of travel).

Default thresholds, measured with the core filter, Nav2's alphas and a 360-beam 3.5 m lidar
(navsuite_testing/nav/fake_lidar.py, 0.01 m noise): driving turtlebot3_world, 52–57 of 60 beams
return, 100 % of them within 0.2 m of a wall, position σ 0.09–0.20 m and yaw σ 0.06–0.23 rad; crossing
the depot_large hall, 0–15 of 60 return and the cloud spreads past 0.3 m (true error 0.23 m)
before it is lost for good (σ 1–6 m, error 0.5–8 m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from enum import Enum

import numpy as np

from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import FloatArray
from nav_stack.core.localization.sensor_model import Beams, DistanceField


class LocalizationState(Enum):
    """Whether the estimate can be trusted (what /diagnostics reports as OK or WARN)."""

    OK = "OK"
    DEGRADED = "DEGRADED"


@dataclass(frozen=True)
class HealthParams:
    """Thresholds of the health check; ROS names ``health.<field>`` under amcl (ratios 0..1)."""

    min_valid_beams_ratio: float = 0.2  # share of AMCL's beams that must return within range_max
    min_matched_ratio: float = 0.5  # share of the returns that must end on a wall at the estimate
    match_distance: float = 0.2  # m to an occupied cell that is "on a wall" (< laser_likelihood_max_dist)
    max_position_std: float = 0.5  # m, the cloud's σ along its widest axis
    max_yaw_std: float = 0.35  # rad (20°)
    bad_updates_to_degrade: int = 5  # consecutive bad filter updates before DEGRADED
    good_updates_to_recover: int = 3  # consecutive good filter updates before OK again

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                raise ValueError(f"HealthParams.{f.name} must be finite, got {value}")
        for name in ("min_valid_beams_ratio", "min_matched_ratio"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"HealthParams.{name} must be in [0, 1], got {getattr(self, name)}")
        for name in ("match_distance", "max_position_std", "max_yaw_std"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"HealthParams.{name} must be > 0, got {getattr(self, name)}")
        for name in ("bad_updates_to_degrade", "good_updates_to_recover"):
            if getattr(self, name) < 1:
                raise ValueError(f"HealthParams.{name} must be >= 1, got {getattr(self, name)}")


@dataclass(frozen=True)
class HealthSample:
    """The evidence of one filter update."""

    beams: int  # beams AMCL kept from the scan (max_beams subsampling)
    returns: int  # of those, readings within range_max
    on_walls: int  # of the returns, endpoints within match_distance of a wall, cast from the estimate
    range_max: float  # m
    position_std: float  # m
    yaw_std: float  # rad

    @property
    def returns_ratio(self) -> float:
        """Share of the beams that returned (0 when there were none)."""
        return self.returns / self.beams if self.beams else 0.0

    @property
    def matched_ratio(self) -> float:
        """Share of the returns that end on a wall (1 when nothing returned: no disagreement)."""
        return self.on_walls / self.returns if self.returns else 1.0

    def describe(self) -> str:
        """The numbers in words, e.g. for the log line that says localization recovered."""
        return (f"{self.returns} of {self.beams} beams returned within {self.range_max:.1f} m, "
                f"{100.0 * self.matched_ratio:.0f} % of them on walls, position σ "
                f"{self.position_std:.2f} m, yaw σ {self.yaw_std:.2f} rad")


def position_std(covariance: FloatArray) -> float:
    """σ (m) along the widest axis of the (x, y) block of a 3×3 (or larger) pose covariance."""
    xy = np.asarray(covariance, dtype=np.float64)[:2, :2]
    return math.sqrt(max(float(np.linalg.eigvalsh(0.5 * (xy + xy.T)).max()), 0.0))


def measure(field: DistanceField, beams: Beams, pose: Pose2D, covariance: FloatArray,
            match_distance: float) -> HealthSample:
    """The evidence of one update: ``beams`` as AMCL used them, the estimate ``pose`` (map frame)
    and the particle covariance (3×3 x, y, yaw)."""
    returned = beams.ranges < beams.range_max  # the beam model keeps max-range readings: not returns
    on_walls = 0
    if returned.any():
        returns = Beams(beams.ranges[returned], beams.bearings[returned], beams.laser_pose, beams.range_max)
        distances = field.at_endpoints(np.array([pose], dtype=np.float64), returns)[0]
        on_walls = int(np.count_nonzero(distances <= match_distance))
    yaw_variance = float(np.asarray(covariance)[2, 2])
    return HealthSample(max(beams.considered, beams.ranges.size), int(returned.sum()), on_walls,
                        beams.range_max, position_std(covariance), math.sqrt(max(yaw_variance, 0.0)))


def problems(sample: HealthSample, params: HealthParams) -> list[str]:
    """What is wrong with one update, each cause with its numbers; empty when the update is good."""
    causes = []
    if sample.returns_ratio < params.min_valid_beams_ratio:
        causes.append(f"few beams on walls: {sample.returns} of {sample.beams} beams returned within "
                      f"{sample.range_max:.1f} m (< {100.0 * params.min_valid_beams_ratio:.0f} %)")
    elif sample.matched_ratio < params.min_matched_ratio:
        causes.append(f"scan disagrees with the map: {100.0 * sample.matched_ratio:.0f} % of returns on "
                      f"walls (< {100.0 * params.min_matched_ratio:.0f} %)")
    spread = []
    if sample.position_std > params.max_position_std:
        spread.append(f"position σ {sample.position_std:.2f} m > {params.max_position_std:.2f} m")
    if sample.yaw_std > params.max_yaw_std:
        spread.append(f"yaw σ {sample.yaw_std:.2f} rad > {params.max_yaw_std:.2f} rad")
    if spread:
        causes.append("particles spread: " + ", ".join(spread))
    return causes


class HealthMonitor:
    """OK / DEGRADED with hysteresis over consecutive filter updates (see the module docstring)."""

    def __init__(self, params: HealthParams) -> None:
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Start over as OK: a new initial pose is the user saying where the robot is."""
        self.state = LocalizationState.OK
        self.cause = ""  # while DEGRADED: what the latest bad update found
        self.sample: HealthSample | None = None
        self._streak = 0  # consecutive updates that disagree with the current state

    def update(self, sample: HealthSample) -> bool:
        """Fold in one filter update; True when the state changed (the caller logs it once)."""
        self.sample = sample
        causes = problems(sample, self.params)
        bad = bool(causes)
        if bad and self.state is LocalizationState.DEGRADED:
            self.cause = "; ".join(causes)
        if bad == (self.state is LocalizationState.DEGRADED):
            self._streak = 0
            return False
        self._streak += 1
        needed = self.params.bad_updates_to_degrade if bad else self.params.good_updates_to_recover
        if self._streak < needed:
            return False
        self._streak = 0
        self.state = LocalizationState.DEGRADED if bad else LocalizationState.OK
        self.cause = "; ".join(causes)
        return True
