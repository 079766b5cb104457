"""Odometry motion models of nav2_amcl, sampled for all particles at once.

Why: between two filter updates every particle moves by the odometry delta plus noise whose
variance grows with the motion (Probabilistic Robotics, sample_motion_model_odometry). The alphas
are variance coefficients (their square roots are not taken by the user).

Differential (nav2_amcl::DifferentialMotionModel): rot1 = atan2(dy, dx) − θ_old (0 when the
translation is below 1 cm), trans = hypot(dx, dy), rot2 = Δθ − rot1. For the noise, rot1/rot2 are
folded to min(|r|, |π − r|) so driving backwards counts like driving forwards:
var(rot1) = α1·rot1² + α2·trans², var(trans) = α3·trans² + α4·(rot1² + rot2²),
var(rot2) = α1·rot2² + α2·trans².

Omni (nav2_amcl::OmniMotionModel): translation along the odometry bearing, a strafe across it with
var = α1·rot² + α5·trans², var(trans) = α3·trans² + α1·rot², var(rot) = α4·rot² + α2·trans².
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.geometry import Pose2D, angle_diff, normalize_angles
from nav_stack.core.grid import FloatArray
from nav_stack.core.localization.params import OMNI


def sample_differential(particles: FloatArray, old: Pose2D, new: Pose2D, alphas: tuple[float, ...],
                        rng: np.random.Generator) -> None:
    """Move ``particles`` (N, 3) in place by the noisy odometry step ``old`` → ``new`` (odom frame)."""
    a1, a2, a3, a4 = alphas[:4]
    dx, dy = new[0] - old[0], new[1] - old[1]
    trans = math.hypot(dx, dy)
    rot1 = 0.0 if trans < 0.01 else angle_diff(math.atan2(dy, dx), old[2])
    rot2 = angle_diff(angle_diff(new[2], old[2]), rot1)
    rot1_n = min(abs(angle_diff(rot1, 0.0)), abs(angle_diff(rot1, math.pi)))
    rot2_n = min(abs(angle_diff(rot2, 0.0)), abs(angle_diff(rot2, math.pi)))
    n = particles.shape[0]
    noise = rng.standard_normal((3, n))
    rot1_hat = rot1 - math.sqrt(a1 * rot1_n**2 + a2 * trans**2) * noise[0]
    trans_hat = trans - math.sqrt(a3 * trans**2 + a4 * (rot1_n**2 + rot2_n**2)) * noise[1]
    rot2_hat = rot2 - math.sqrt(a1 * rot2_n**2 + a2 * trans**2) * noise[2]
    heading = particles[:, 2] + rot1_hat
    particles[:, 0] += trans_hat * np.cos(heading)
    particles[:, 1] += trans_hat * np.sin(heading)
    particles[:, 2] = normalize_angles(heading + rot2_hat)


def sample_omni(particles: FloatArray, old: Pose2D, new: Pose2D, alphas: tuple[float, ...],
                rng: np.random.Generator) -> None:
    """Move ``particles`` (N, 3) in place by the noisy holonomic odometry step ``old`` → ``new``."""
    a1, a2, a3, a4, a5 = alphas[:5]
    dx, dy = new[0] - old[0], new[1] - old[1]
    trans = math.hypot(dx, dy)
    rot = angle_diff(new[2], old[2])
    n = particles.shape[0]
    noise = rng.standard_normal((3, n))
    trans_hat = trans + math.sqrt(a3 * trans**2 + a1 * rot**2) * noise[0]
    rot_hat = rot + math.sqrt(a4 * rot**2 + a2 * trans**2) * noise[1]
    strafe_hat = math.sqrt(a1 * rot**2 + a5 * trans**2) * noise[2]
    bearing = angle_diff(math.atan2(dy, dx), old[2]) + particles[:, 2]
    cs, sn = np.cos(bearing), np.sin(bearing)
    particles[:, 0] += trans_hat * cs + strafe_hat * sn
    particles[:, 1] += trans_hat * sn - strafe_hat * cs
    particles[:, 2] = normalize_angles(particles[:, 2] + rot_hat)


def sample_motion(model: str, particles: FloatArray, old: Pose2D, new: Pose2D, alphas: tuple[float, ...],
                  rng: np.random.Generator) -> None:
    """Dispatch on ``robot_model_type``."""
    if model == OMNI:
        sample_omni(particles, old, new, alphas, rng)
    else:
        sample_differential(particles, old, new, alphas, rng)
