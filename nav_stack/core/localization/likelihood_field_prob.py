"""nav2_amcl's ``likelihood_field_prob`` laser model: the likelihood field plus beam skipping.

Why: something that is not in the map (a person, a parked cart) shortens a few beams. At the true
pose those endpoints lie far from every wall, so the product of the per-beam pz punishes exactly
the particles that are right, and a pose that happens to put those endpoints on a wall can win.
Beam skipping drops, for every particle alike, the beams that most particles cannot explain.

Per beam (as Nav2's LikelihoodFieldModelProb, the same pz as the likelihood field of
sensor_model.py, whose table this model reuses): pz = z_hit·exp(−d²/2σ_hit²) + z_rand/range_max,
d (m) the distance from the endpoint to the nearest occupied cell, capped at
``laser_likelihood_max_dist``; an endpoint off the map counts as the cap. NaN and readings
≥ range_max are ignored. Beams: every ``step``-th with step = ceil(count / max_beams), Nav2's rule
for this model (the other two use (count − 1) // (max_beams − 1); see sensor_model.select_beams).

Beam skipping (``do_beamskip``; like Nav2, only while the filter has converged, i.e. every particle
lies within 0.5 m of the mean, since before that "most particles" says nothing about the map):

- a beam agrees with the map for a particle when its endpoint is on the map and strictly closer
  than ``beam_skip_distance`` (m) to an obstacle;
- a beam is integrated when the fraction of particles for which it agrees exceeds
  ``beam_skip_threshold``; the other beams are skipped for every particle;
- Nav2 counts skips over all ``max_beams`` slots, so slots without a valid reading (max range,
  NaN, or unused when the scan has fewer beams) count as skipped. When the skipped slots reach
  ``beam_skip_error_threshold`` · max_beams, the cloud has probably converged to a wrong pose and
  every valid beam is integrated (Nav2 prints "Over 90% of the observations were not in the map").

Weights: Nav2 multiplies each particle's weight by exp(Σ log pz) over the integrated beams, the
product of their pz. :meth:`LikelihoodFieldProbModel.weigh` returns that Σ log pz, and Amcl hands it
to weighting.reweight like the other models' log-likelihoods: the same product, raised to the
tempering exponent γ ≤ 1 that keeps the effective sample size at ``min_ess_ratio`` (with
``min_ess_ratio`` 0, exactly Nav2's weights after normalisation). The w_slow/w_fast fit of a scan
is the per-beam geometric mean over the integrated beams only, so skipping does not lower it.

Differences from Nav2: in the "too many skipped" case Nav2 also multiplies in whatever its
per-beam buffer held from an earlier scan for the slots without a valid reading; here only this
scan's valid readings count. Endpoints and the log pz table are float64 (the plain likelihood field
uses float32 for speed), so the result matches a scalar reference to 1e-9; bench/bench_amcl.py
measures what that and the skipping cost.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.grid import FloatArray, GridSpec
from nav_stack.core.localization.params import AmclParams
from nav_stack.core.localization.sensor_model import Beams, LikelihoodFieldModel

BoolArray = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class ScanWeights:
    """What one scan did in the likelihood_field_prob model.

    Attributes:
        log_likelihood: Σ log pz over the integrated beams, per particle, shape (N,).
        integrated: which of the scan's valid beams (Beams order) were integrated, shape (B,).
        agreement: fraction of particles for which each beam agreed with the map, shape (B,);
            all zero when beam skipping did not run.
        skipping: True when beam skipping ran (do_beamskip and a converged filter).
        too_many_skipped: True when skipping would have dropped at least beam_skip_error_threshold
            of max_beams, so every valid beam was integrated instead.
    """

    log_likelihood: FloatArray
    integrated: BoolArray
    agreement: FloatArray
    skipping: bool = False
    too_many_skipped: bool = False

    @property
    def integrated_count(self) -> int:
        """How many beams each particle's likelihood multiplies."""
        return int(np.count_nonzero(self.integrated))

    @property
    def skipped_count(self) -> int:
        """How many valid beams were left out (0 unless beam skipping dropped some)."""
        return int(self.integrated.size - self.integrated_count)


class LikelihoodFieldProbModel(LikelihoodFieldModel):
    """The likelihood field with Nav2's beam skipping (see the module docstring)."""

    precision: npt.DTypeLike = np.float64

    def __init__(self, occupancy: npt.NDArray[np.int8], spec: GridSpec, params: AmclParams) -> None:
        super().__init__(occupancy, spec, params)
        near = self.field.values < params.beam_skip_distance
        near[0, :] = near[-1, :] = near[:, 0] = near[:, -1] = False  # off the map never agrees
        self._near = near.ravel()

    def weigh(self, particles: FloatArray, beams: Beams, converged: bool) -> ScanWeights:
        """Σ log pz per particle over the beams beam skipping keeps (all when it does not run).

        Args:
            particles: (N, 3) poses x (m), y (m), yaw (rad) in the map frame.
            beams: the scan's valid beams, selected with this model's step.
            converged: whether the filter has converged; beam skipping runs only then.
        """
        p = self.params
        count = beams.ranges.size
        every = np.ones(count, dtype=bool)
        if count == 0 or particles.shape[0] == 0:
            return ScanWeights(np.zeros(particles.shape[0]), every, np.zeros(count))
        indices = self.field.endpoint_indices(particles, beams, self.precision)
        log_pz = self._table(beams.range_max).take(indices)
        if not (p.do_beamskip and converged):
            return ScanWeights(log_pz.sum(axis=1), every, np.zeros(count))
        agreement = np.count_nonzero(self._near.take(indices), axis=0) / particles.shape[0]
        keep = agreement > p.beam_skip_threshold
        too_many = p.max_beams - int(np.count_nonzero(keep)) >= p.max_beams * p.beam_skip_error_threshold
        if too_many:
            keep = every
        total: FloatArray = log_pz @ keep.astype(np.float64)  # a mat-vec: cheaper than a masked copy
        return ScanWeights(total, keep, agreement, True, too_many)

    def log_likelihood(self, particles: FloatArray, beams: Beams) -> FloatArray:
        """Σ log pz over every valid beam, per particle (N,): the model without beam skipping."""
        return self.weigh(particles, beams, converged=False).log_likelihood
