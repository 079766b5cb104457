"""Adaptive Monte Carlo Localization: the pure filter behind the amcl node (nav2_amcl semantics).

Why: the node only turns /initialpose, /scan, TF and the map into calls here and publishes what
comes back (``amcl_pose`` from :meth:`Amcl.estimate`, ``particle_cloud`` from :attr:`particles`,
and map→odom from :func:`map_to_odom`). Everything is vectorised over particles; the RNG is injected.

Cycle per scan (:meth:`Amcl.update`): the first scan after an initial pose only stores the odometry
and weights the particles; later scans update only when the odometry moved more than update_min_d
(|dx| or |dy|) or update_min_a since the last update. An update is: motion model → laser weights →
w_slow / w_fast tracking → every ``resample_interval`` updates, KLD-sized low-variance resampling
with uniform free-space injection at probability max(0, 1 − w_fast/w_slow). Laser models
(``laser_model_type``): likelihood_field and beam (sensor_model.py), likelihood_field_prob with beam
skipping (likelihood_field_prob.py), which skips beams only once :attr:`Amcl.converged`.

Deliberate differences from nav2_amcl, each measured on the turtlebot3_world tour (see
weighting.py and bench/RESULTS.md): the laser weight is the tempered product of the per-beam pz,
not Nav2's 1 + Σ pz³ (which leaves 0.1–0.3 m of error even with perfect odometry); the recovery
averages start as running means and w_slow does not learn from unhealthy scans (Nav2 seeds both
with the first scan and resets them after each injection). Resampling is low-variance
(systematic) with the count chosen by Nav2's KLD loop (see kld.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import IDENTITY, Pose2D, angle_diff, normalize_angles
from nav_stack.core.grid import FloatArray, GridSpec
from nav_stack.core.localization.clusters import PoseEstimate, estimate_pose
from nav_stack.core.localization.kld import bin_keys, kld_sample_count
from nav_stack.core.localization.likelihood_field_prob import LikelihoodFieldProbModel, ScanWeights
from nav_stack.core.localization.motion_model import sample_motion
from nav_stack.core.localization.params import BEAM, LIKELIHOOD_FIELD_PROB, AmclParams
from nav_stack.core.localization.sensor_model import (
    BeamModel,
    Beams,
    DistanceField,
    LikelihoodFieldModel,
    select_beams,
)
from nav_stack.core.localization.weighting import FitAverages, reweight

DEFAULT_INITIAL_COVARIANCE = np.diag([0.5**2, 0.5**2, (math.pi / 12.0) ** 2])
CONVERGED_DISTANCE = 0.5  # m, nav2 pf dist_threshold


@dataclass(frozen=True)
class UpdateResult:
    """What one scan did to the filter."""

    updated: bool
    resampled: bool = False


def map_to_odom(map_to_base: Pose2D, odom_to_base: Pose2D) -> Pose2D:
    """The map→odom transform that makes map→odom→base equal the estimate: T_mb · T_ob⁻¹."""
    mx, my, myaw = map_to_base
    ox, oy, oyaw = odom_to_base
    yaw = angle_diff(myaw, oyaw)
    c, s = math.cos(yaw), math.sin(yaw)
    return Pose2D(mx - (c * ox - s * oy), my - (s * ox + c * oy), yaw)


def low_variance_indices(weights: FloatArray, count: int, rng: np.random.Generator) -> npt.NDArray[np.int64]:
    """Systematic (low-variance) resampling: ``count`` indices drawn with one random offset."""
    cumulative = np.cumsum(weights)
    cumulative /= cumulative[-1]
    points = (rng.random() + np.arange(count)) / count
    idx: npt.NDArray[np.int64] = np.searchsorted(cumulative, points, side="right")
    np.minimum(idx, weights.size - 1, out=idx)
    return idx


class Amcl:
    """The particle filter on one map."""

    def __init__(self, params: AmclParams, occupancy: npt.NDArray[np.int8], spec: GridSpec,
                 rng: np.random.Generator) -> None:
        if occupancy.shape != spec.shape:
            raise ValueError(f"map data shape {occupancy.shape} does not match grid {spec.shape}")
        self.params = params
        self.spec = spec
        self.rng = rng
        self.model: LikelihoodFieldModel | LikelihoodFieldProbModel | BeamModel = (
            BeamModel(occupancy, spec, params) if params.laser_model_type == BEAM
            else LikelihoodFieldProbModel(occupancy, spec, params)
            if params.laser_model_type == LIKELIHOOD_FIELD_PROB
            else LikelihoodFieldModel(occupancy, spec, params))
        #: Distance to the nearest wall, for checking a scan against the map at the estimate (health.py).
        self.distance_field = (self.model.field if isinstance(self.model, LikelihoodFieldModel)
                               else DistanceField(occupancy, spec, params.laser_likelihood_max_dist))
        free_my, free_mx = np.nonzero(occupancy == 0)
        self._free_cells = np.column_stack([free_mx, free_my])
        self.particles: FloatArray = np.zeros((0, 3))
        self.weights: FloatArray = np.zeros(0)
        self.fit = FitAverages(params.recovery_alpha_slow, params.recovery_alpha_fast)
        self.last_beams: Beams | None = None  # the beams the last laser update weighed the particles with
        self.last_scan_weights: ScanWeights | None = None  # likelihood_field_prob: what beam skipping did
        self.converged = False
        self._odom_at_update: Pose2D | None = None
        self._force_update = False
        self._resample_count = 0
        self._alphas = (params.alpha1, params.alpha2, params.alpha3, params.alpha4, params.alpha5)

    @property
    def initialized(self) -> bool:
        """True once an initial pose or global localization has seeded the particles."""
        return bool(self.particles.shape[0] > 0)

    def _reset(self, particles: FloatArray) -> None:
        self.particles = particles
        self.weights = np.full(particles.shape[0], 1.0 / particles.shape[0])
        self.fit.reset()
        self.converged = False
        self.last_beams = None
        self.last_scan_weights = None
        self._odom_at_update = None
        self._resample_count = 0

    def set_initial_pose(
        self, x: float, y: float, yaw: float, covariance: npt.ArrayLike | None = None
    ) -> None:
        """Spread ``max_particles`` around a pose (map frame) with a 3×3 (x, y, yaw) covariance.

        Raises ValueError (with the reason) for a non-finite pose, a pose off the map, or a
        covariance that is not a finite, symmetric, positive semi-definite 3×3 matrix.
        """
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            raise ValueError(f"initial pose must be finite, got x={x}, y={y}, yaw={yaw}")
        if not self.spec.contains_point(x, y):
            w, h = self.spec.size_m
            raise ValueError(f"initial pose ({x:.3f}, {y:.3f}) lies outside the map, which spans x "
                             f"[{self.spec.origin_x:.2f}, {self.spec.origin_x + w:.2f}] and y "
                             f"[{self.spec.origin_y:.2f}, {self.spec.origin_y + h:.2f}] (origin yaw ignored)")
        cov = DEFAULT_INITIAL_COVARIANCE if covariance is None else np.asarray(covariance, dtype=np.float64)
        if cov.shape != (3, 3) or not np.all(np.isfinite(cov)):
            raise ValueError(f"initial pose covariance must be a finite 3x3 matrix, got {cov.tolist()}")
        if not np.allclose(cov, cov.T, atol=1e-9):
            raise ValueError(f"initial pose covariance must be symmetric, got {cov.tolist()}")
        eigval, eigvec = np.linalg.eigh(cov)
        if eigval.min() < -1e-9:
            raise ValueError(
                f"initial pose covariance must be positive semi-definite (eigenvalues {eigval.tolist()})")
        n = self.params.max_particles
        noise = self.rng.standard_normal((n, 3)) * np.sqrt(np.maximum(eigval, 0.0))
        particles = np.array([x, y, yaw]) + noise @ eigvec.T
        particles[:, 2] = normalize_angles(particles[:, 2])
        self._reset(particles)

    def random_free_poses(self, count: int) -> FloatArray:
        """``count`` poses uniform over the map's free cells (value 0) with uniform yaw."""
        if self._free_cells.shape[0] == 0:
            raise ValueError("the map has no free cell to place particles in")
        cells = self._free_cells[self.rng.integers(0, self._free_cells.shape[0], count)]
        wx, wy = self.spec.cell_to_world(cells[:, 0], cells[:, 1])
        jitter = (self.rng.random((count, 2)) - 0.5) * self.spec.resolution  # anywhere inside the cell
        c, s = math.cos(self.spec.origin_yaw), math.sin(self.spec.origin_yaw)
        wx = wx + c * jitter[:, 0] - s * jitter[:, 1]
        wy = wy + s * jitter[:, 0] + c * jitter[:, 1]
        yaw = self.rng.uniform(-math.pi, math.pi, count)
        return np.column_stack([wx, wy, yaw])

    def global_localization(self) -> None:
        """Spread ``max_particles`` uniformly over free space (reinitialize_global_localization)."""
        self._reset(self.random_free_poses(self.params.max_particles))

    def request_nomotion_update(self) -> None:
        """Force a sensor update (and resample) at the next scan even if the robot has not moved."""
        self._force_update = True

    def update(
        self, odom_pose: Pose2D, scan: LaserScan, laser_pose: Pose2D = IDENTITY
    ) -> UpdateResult:
        """Process one scan taken at odometry pose ``odom_pose``; ``laser_pose``: laser in the base frame."""
        if not self.initialized:
            return UpdateResult(False)
        if not all(math.isfinite(v) for v in odom_pose):
            raise ValueError(f"odometry pose must be finite, got {odom_pose}")
        last = self._odom_at_update
        if last is not None:
            moved = (abs(odom_pose[0] - last[0]) > self.params.update_min_d
                     or abs(odom_pose[1] - last[1]) > self.params.update_min_d
                     or abs(angle_diff(odom_pose[2], last[2])) > self.params.update_min_a)
            if not (moved or self._force_update):
                return UpdateResult(False)
            sample_motion(self.params.robot_model_type, self.particles, last, odom_pose, self._alphas,
                          self.rng)
        self._force_update = False
        self._odom_at_update = odom_pose
        self._sensor_update(scan, laser_pose)
        self._resample_count += 1
        resampled = self._resample_count % self.params.resample_interval == 0
        if resampled:
            self._resample()
        return UpdateResult(True, resampled)

    def _sensor_update(self, scan: LaserScan, laser_pose: Pose2D) -> None:
        beams = select_beams(scan, laser_pose, self.params, keep_max=self.params.laser_model_type == BEAM)
        self.last_beams = beams
        if beams.ranges.size == 0:
            return  # nothing seen: every particle stays as likely as it was
        if isinstance(self.model, LikelihoodFieldProbModel):
            self.last_scan_weights = self.model.weigh(self.particles, beams, self.converged)
            log_l, integrated = self.last_scan_weights.log_likelihood, self.last_scan_weights.integrated_count
        else:
            log_l, integrated = self.model.log_likelihood(self.particles, beams), beams.ranges.size
        self.fit.add(FitAverages.scan_fit(self.weights, log_l, integrated))
        self.weights, _gamma = reweight(self.weights, log_l, self.params.min_ess_ratio)

    def _resample(self) -> None:
        p = self.params
        w_diff = self.fit.injection_probability
        draw = self._draw(p.max_particles, w_diff)
        count = kld_sample_count(bin_keys(draw), p.pf_err, p.pf_z, p.min_particles, p.max_particles)
        particles = self._draw(count, w_diff)
        self.particles = particles
        self.weights = np.full(count, 1.0 / count)
        mean = particles[:, :2].mean(axis=0)
        self.converged = bool(np.all(np.abs(particles[:, :2] - mean) <= CONVERGED_DISTANCE))

    def _draw(self, count: int, w_diff: float) -> FloatArray:
        """``count`` new particles: low-variance copies of the current set, some replaced by random ones."""
        drawn = self.particles[low_variance_indices(self.weights, count, self.rng)]
        drawn = drawn[self.rng.permutation(count)]
        if w_diff > 0.0:
            inject = self.rng.random(count) < w_diff
            if inject.any():
                drawn[inject] = self.random_free_poses(int(inject.sum()))
        return drawn

    def estimate(self) -> PoseEstimate:
        """Mean of the heaviest particle cluster, with the set's covariance."""
        if not self.initialized:
            raise RuntimeError("AMCL has no particles yet: set an initial pose or run global localization")
        return estimate_pose(self.particles, self.weights)
