"""Laser models of nav2_amcl: likelihood field (default) and beam, vectorised over particles × beams.

Why: the sensor update dominates AMCL's cost. The likelihood field depends only on the map, so the
per-cell term log pz is precomputed once per range_max and one scan update is: two small matrix
products that place every beam endpoint of every particle in grid cells, one integer gather, one
row sum. Off-map endpoints read a one-cell border that holds the "max distance" value.

Likelihood field: the distance d (m) from each cell centre to the nearest occupied cell (value 100),
capped at ``laser_likelihood_max_dist``; per beam pz = z_hit·exp(−d²/2σ_hit²) + z_rand/range_max.
Beam model: the expected range is ray-cast in the map (stopping at any non-free cell), and
pz = z_hit·exp(−Δ²/2σ²) + z_short·λ·e^{−λr} (if shorter) + z_max (if r = range_max) + z_rand/range_max.
Both return Σ log pz per particle (the log of the product over beams); how that becomes a weight,
and why it is not Nav2's 1 + Σ pz³, is in weighting.py.

Beams: Nav2 keeps every ``step``-th beam with step = (count − 1) // (max_beams − 1) (at least 1), drops
NaN and readings ≥ range_max; readings ≤ range_min are treated as range_max (thus dropped too).
Nav2's likelihood_field_prob steps by ceil(count / max_beams) instead (likelihood_field_prob.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.distance import squared_distance_cells
from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import FloatArray, GridSpec
from nav_stack.core.localization.params import LIKELIHOOD_FIELD_PROB, AmclParams

F32 = npt.NDArray[np.float32]
FloatTable = npt.NDArray[np.floating[Any]]
_TINY = 1e-300  # floor of pz, so log pz stays finite when z_rand = 0


@dataclass(frozen=True)
class Beams:
    """The beams of one scan used for weighting, in the robot base frame."""

    ranges: FloatArray
    bearings: FloatArray  # rad, base frame
    laser_pose: Pose2D
    range_max: float
    considered: int = 0  # beams the subsampling kept, before NaN and max-range readings were dropped


def select_beams(scan: LaserScan, laser_pose: Pose2D, params: AmclParams, keep_max: bool = False) -> Beams:
    """Subsample and filter a scan as nav2_amcl does (see module doc)."""
    range_max = scan.range_max if params.laser_max_range <= 0 else min(scan.range_max, params.laser_max_range)
    range_min = scan.range_min if params.laser_min_range <= 0 else max(scan.range_min, params.laser_min_range)
    ranges = np.asarray(scan.ranges, dtype=np.float64).copy()
    ranges[ranges <= range_min] = range_max
    if params.laser_model_type == LIKELIHOOD_FIELD_PROB:
        step = max(1, -(-len(ranges) // params.max_beams))  # ceil(count / max_beams)
    else:
        step = max(1, (len(ranges) - 1) // (params.max_beams - 1))
    idx = np.arange(0, len(ranges), step)
    r = ranges[idx]
    bearing = scan.angles[idx] + laser_pose[2]
    valid = ~np.isnan(r) & ((r <= range_max) if keep_max else (r < range_max))
    return Beams(np.minimum(r[valid], range_max), bearing[valid], laser_pose, range_max, int(r.size))


class GridLookup:
    """Turns particle poses into grid frame coordinates (handles a rotated map origin)."""

    def __init__(self, spec: GridSpec) -> None:
        self.spec = spec
        self._c, self._s = math.cos(spec.origin_yaw), math.sin(spec.origin_yaw)

    def to_grid(self, particles: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Particle x, y in cells (continuous) and yaw, in the unrotated grid frame."""
        dx, dy = particles[:, 0] - self.spec.origin_x, particles[:, 1] - self.spec.origin_y
        gx = (self._c * dx + self._s * dy) / self.spec.resolution
        gy = (-self._s * dx + self._c * dy) / self.spec.resolution
        return gx, gy, particles[:, 2] - self.spec.origin_yaw


def _endpoints(lookup: GridLookup, particles: FloatArray, beams: Beams,
               dtype: npt.DTypeLike = np.float32) -> tuple[FloatTable, FloatTable]:
    """Beam endpoints of every particle in continuous cell coordinates, shape (N, B), in ``dtype``."""
    lx, ly, _ = beams.laser_pose
    inv = 1.0 / lookup.spec.resolution
    ex = (lx + beams.ranges * np.cos(beams.bearings)) * inv
    ey = (ly + beams.ranges * np.sin(beams.bearings)) * inv
    basis = np.stack([ex, ey, np.ones_like(ex)]).astype(dtype)  # (3, B)
    gx, gy, yaw = lookup.to_grid(particles)
    c, s = np.cos(yaw), np.sin(yaw)
    rows_x = np.stack([c, -s, gx], axis=1).astype(dtype)  # (N, 3)
    rows_y = np.stack([s, c, gy], axis=1).astype(dtype)
    return rows_x @ basis, rows_y @ basis


class DistanceField:
    """Distance (m) from each cell centre to the nearest occupied cell (value 100), capped at ``max_dist``.

    Why a class of its own: the likelihood field turns it into per-beam probabilities, and the
    localization health check (health.py) asks the same question of a single pose: how far from a
    wall does each beam end? ``values`` is (H + 2, W + 2) with a one-cell border holding ``max_dist``,
    so an endpoint off the map reads "far from everything" without a bounds check.
    """

    def __init__(self, occupancy: npt.NDArray[np.int8], spec: GridSpec, max_dist: float) -> None:
        self.lookup = GridLookup(spec)
        max_cells = math.ceil(max_dist / spec.resolution)
        d2 = squared_distance_cells(occupancy == 100, max_cells)
        padded = np.full((spec.height + 2, spec.width + 2), max_dist)
        padded[1:-1, 1:-1] = np.minimum(np.sqrt(d2) * spec.resolution, max_dist)
        self.values = padded

    def endpoint_indices(self, particles: FloatArray, beams: Beams,
                         dtype: npt.DTypeLike = np.float32) -> npt.NDArray[np.int32]:
        """Flat index into ``values`` of every beam endpoint of every particle, shape (N, B).

        ``dtype`` is the precision of the endpoint arithmetic: float32 is faster; float64 places
        endpoints within a hair of a cell edge in the same cell as a scalar float64 computation.
        """
        spec = self.lookup.spec
        gx, gy = _endpoints(self.lookup, particles, beams, dtype)
        ix = np.clip(gx + 1.0, 0.0, spec.width + 1.0, out=gx).astype(np.int32)
        iy = np.clip(gy + 1.0, 0.0, spec.height + 1.0, out=gy).astype(np.int32)
        iy *= spec.width + 2
        iy += ix
        return iy

    def at_endpoints(self, particles: FloatArray, beams: Beams) -> FloatArray:
        """Distance (m) from every beam endpoint of every particle to the nearest wall, shape (N, B)."""
        distances: FloatArray = self.values.ravel().take(self.endpoint_indices(particles, beams))
        return distances


class LikelihoodFieldModel:
    """Precomputed likelihood field of an occupancy map.

    ``precision`` (class attribute): dtype of the endpoint arithmetic and of the log pz table; float32
    halves the memory traffic of the hot loop, and a subclass may ask for float64.
    """

    precision: npt.DTypeLike = np.float32

    def __init__(self, occupancy: npt.NDArray[np.int8], spec: GridSpec, params: AmclParams) -> None:
        self.params = params
        self.field = DistanceField(occupancy, spec, params.laser_likelihood_max_dist)
        self._tables: dict[float, FloatTable] = {}

    def _table(self, range_max: float) -> FloatTable:
        """log pz of an endpoint in each cell of ``field.values`` (flat), for scans with ``range_max``."""
        table = self._tables.get(range_max)
        if table is None:
            p = self.params
            distance = self.field.values
            pz = p.z_hit * np.exp(-(distance**2) / (2.0 * p.sigma_hit**2)) + p.z_rand / range_max
            table = np.log(np.maximum(pz, _TINY)).astype(self.precision).ravel()
            self._tables = {range_max: table}
        return table

    def log_likelihood(self, particles: FloatArray, beams: Beams) -> FloatArray:
        """Σ log pz over the beams, for each particle (N,)."""
        if beams.ranges.size == 0:
            return np.zeros(particles.shape[0])
        indices = self.field.endpoint_indices(particles, beams, self.precision)
        total: FloatArray = self._table(beams.range_max).take(indices).sum(axis=1, dtype=np.float64)
        return total


class BeamModel:
    """Ray-casting beam model (slower; marches every beam of every particle through the map)."""

    def __init__(self, occupancy: npt.NDArray[np.int8], spec: GridSpec, params: AmclParams) -> None:
        self.params = params
        self.lookup = GridLookup(spec)
        blocked = np.ones((spec.height + 2, spec.width + 2), dtype=bool)
        blocked[1:-1, 1:-1] = occupancy != 0
        self._blocked = blocked.ravel()

    def expected_ranges(self, particles: FloatArray, beams: Beams) -> FloatArray:
        """Distance (m) from each particle's laser to the first non-free cell along each beam (N, B)."""
        spec, p = self.lookup.spec, beams.laser_pose
        gx, gy, yaw = self.lookup.to_grid(particles)
        c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
        sx = gx[:, None] + (c * p[0] - s * p[1]) / spec.resolution
        sy = gy[:, None] + (s * p[0] + c * p[1]) / spec.resolution
        heading = yaw[:, None] + beams.bearings[None, :]
        ux, uy = np.cos(heading), np.sin(heading)
        max_cells = beams.range_max / spec.resolution
        result = np.full(heading.shape, beams.range_max)
        open_ = np.ones(heading.shape, dtype=bool)
        step = 0.5
        t = 0.0
        while t <= max_cells and open_.any():
            ix = np.clip(sx + ux * t + 1.0, 0.0, spec.width + 1.0).astype(np.int64)
            iy = np.clip(sy + uy * t + 1.0, 0.0, spec.height + 1.0).astype(np.int64)
            hit = open_ & self._blocked[iy * (spec.width + 2) + ix]
            result[hit] = t * spec.resolution
            open_ &= ~hit
            t += step
        return result

    def log_likelihood(self, particles: FloatArray, beams: Beams) -> FloatArray:
        """Σ log pz over the beams, for each particle (N,)."""
        if beams.ranges.size == 0:
            return np.zeros(particles.shape[0])
        p = self.params
        obs = beams.ranges[None, :]
        z = obs - self.expected_ranges(particles, beams)
        pz = p.z_hit * np.exp(-(z**2) / (2.0 * p.sigma_hit**2))
        pz = pz + np.where(z < 0, p.z_short * p.lambda_short * np.exp(-p.lambda_short * obs), 0.0)
        pz = pz + np.where(obs >= beams.range_max, p.z_max, p.z_rand / beams.range_max)
        out: FloatArray = np.log(np.maximum(pz, _TINY)).sum(axis=1)
        return out
