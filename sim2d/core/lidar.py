"""A planar 360° lidar (the TurtleBot3's LDS-01 or the TurtleBot4's RPLIDAR A1), ray cast with numpy.

Each robot model carries its sensor's figures (LDS_01, RPLIDAR_A1 below); LidarParams' defaults are
the LDS-01's. Output follows REP 117: +inf for no return within range_max (also for a dropped
beam), -inf for a return closer than range_min.

:func:`cast_rays` is the reference caster: every beam is intersected with every nearby segment and
circle at once, a handful of array operations. A :class:`Lidar` casts with lidar_jit.BinnedCaster
unless given another caster: the same ranges (tests/unit/sim2d/test_lidar_jit.py), each beam testing
only the items near its path, which is what keeps scans cheap on warehouse-sized worlds (issue 44).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from sim2d.core.geometry import BoolArray, FloatArray, StaticGeometry


@dataclass(frozen=True)
class LidarParams:
    """Lidar configuration.

    Attributes:
        beams: number of rays, evenly spread over ``angle_span`` (rad) from ``angle_min`` (rad).
        range_min, range_max: valid return interval (m).
        rate: scans per second of sim time (Hz).
        noise_stddev: Gaussian range noise σ (m).
        dropout_probability: chance per beam of no return (+inf).
    """

    beams: int = 360
    angle_min: float = 0.0
    angle_span: float = 2.0 * math.pi
    range_min: float = 0.12
    range_max: float = 3.5
    rate: float = 5.0
    noise_stddev: float = 0.01
    dropout_probability: float = 0.0

    def __post_init__(self) -> None:
        checks = {
            "beams": self.beams >= 1, "angle_span": 0.0 < self.angle_span <= 2.0 * math.pi + 1e-9,
            "range_min": self.range_min >= 0.0, "range_max": self.range_max > self.range_min,
            "rate": self.rate > 0.0, "noise_stddev": self.noise_stddev >= 0.0,
            "dropout_probability": 0.0 <= self.dropout_probability <= 1.0,
        }
        for name, ok in checks.items():
            if not ok:
                raise ValueError(f"lidar.{name}: invalid value {getattr(self, name)!r}")

    @property
    def angle_increment(self) -> float:
        """Angle between beams (rad)."""
        return self.angle_span / self.beams

    @property
    def angle_max(self) -> float:
        """Angle of the last beam (rad), as LaserScan.angle_max defines it."""
        return self.angle_min + (self.beams - 1) * self.angle_increment


#: TurtleBot3 LDS-01 (reference/nav2.md §6, ROBOTIS gazebo model): 360 beams over 360° from 0 rad,
#: 0.12–3.5 m, 5 Hz, Gaussian range noise σ = 0.01 m.
LDS_01 = LidarParams()

#: TurtleBot4 RPLIDAR A1M8. Slamtec A1 datasheet: 0.15–12 m, 360 samples per turn (1°) at its typical
#: 5.5 Hz scan rate (Nav2's minimal TB4 sim runs its gz lidar at 10 Hz, 0.164–20 m; the real sensor
#: is taken here). Beam 0 at 0 rad of the sensor frame, as that sim's rplidar (0 to 2π). Range noise
#: σ = 0.01 m is an assumption: the datasheet gives a resolution (< 0.5 mm under 1.5 m, < 1 % of the
#: distance), not a noise figure.
RPLIDAR_A1 = LidarParams(beams=360, angle_min=0.0, range_min=0.15, range_max=12.0, rate=5.5,
                         noise_stddev=0.01)


#: (sensor origin (m), beam angles (rad, map frame), geometry, max range (m)) -> ranges (m), +inf for none:
#: :func:`cast_rays` or lidar_jit.BinnedCaster()
Caster = Callable[[tuple[float, float], FloatArray, StaticGeometry, float], FloatArray]


def cast_rays(origin: tuple[float, float], angles: FloatArray, geometry: StaticGeometry,
              max_range: float) -> FloatArray:
    """Distance (B,) (m) along each ray from ``origin`` to the first obstacle, +inf beyond ``max_range``.

    Segments are oriented with the obstacle on their left, so those facing away from the origin
    (never the first hit) and those out of range are culled before the (B, N) intersection.
    """
    ox, oy = origin
    dx, dy = np.cos(angles)[:, None], np.sin(angles)[:, None]
    best = np.full(len(angles), np.inf)
    seg = geometry.ray_segments
    if len(seg):
        px, py = seg[:, 0] - ox, seg[:, 1] - oy
        ex, ey = seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]
        numerator = py * ex - px * ey                     # t · (e × d): > 0 when the segment faces us
        keep = (numerator > 0.0) & _segments_near(seg, ox, oy, max_range)
        px, py, ex, ey, numerator = px[keep], py[keep], ex[keep], ey[keep], numerator[keep]
        if len(px):
            denom = dy * ex - dx * ey                     # (B, N); > 0 for beams that can hit the face
            u_num = py * dx - px * dy                     # u · denom
            hit = (denom > 0.0) & (u_num >= 0.0) & (u_num <= denom)
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.where(hit, numerator / denom, np.inf)
            best = np.minimum(best, t.min(axis=1))
    circles = geometry.circles
    if len(circles):
        cx, cy = circles[:, 0] - ox, circles[:, 1] - oy
        near = cx * cx + cy * cy <= (max_range + circles[:, 2]) ** 2
        cx, cy, radius = cx[near], cy[near], circles[near, 2]
        if len(cx):
            b = dx * cx + dy * cy                         # projection of each centre on each ray
            disc = b * b - (cx * cx + cy * cy - radius * radius)
            root = np.sqrt(np.maximum(disc, 0.0))
            t = np.where(b >= root, b - root, b + root)   # origin inside a circle: its exit point
            t = np.where((disc >= 0.0) & (b + root >= 0.0), t, np.inf)
            best = np.minimum(best, t.min(axis=1))
    best[best > max_range] = np.inf
    return best


def _segments_near(seg: FloatArray, ox: float, oy: float, max_range: float) -> BoolArray:
    """Mask of segments whose bounding box comes within ``max_range`` of the origin (cheap cull)."""
    x_low, x_high = np.minimum(seg[:, 0], seg[:, 2]), np.maximum(seg[:, 0], seg[:, 2])
    y_low, y_high = np.minimum(seg[:, 1], seg[:, 3]), np.maximum(seg[:, 1], seg[:, 3])
    gap_x = np.maximum(x_low - ox, 0.0) + np.maximum(ox - x_high, 0.0)
    gap_y = np.maximum(y_low - oy, 0.0) + np.maximum(oy - y_high, 0.0)
    result: BoolArray = gap_x * gap_x + gap_y * gap_y <= max_range * max_range
    return result


class Lidar:
    """Produces noisy REP 117 scans from a sensor pose; the noise comes from the injected generator."""

    def __init__(self, params: LidarParams, geometry: StaticGeometry, rng: np.random.Generator,
                 caster: Caster | None = None) -> None:
        """``caster``: None for the compiled lidar_jit.BinnedCaster, or :func:`cast_rays`, the reference.

        numba is imported here, not with the module: tools that only read LidarParams stay light.
        """
        self._cast_moving: Caster = cast_rays    # the reference casts moving bodies too
        if caster is None:
            from sim2d.core import lidar_jit

            lidar_jit.warm_up()  # compile or load it now, not in the first scan
            caster = lidar_jit.BinnedCaster()
            self._cast_moving = lidar_jit.cast_each
        self._cast = caster
        self.params = params
        self.geometry = geometry
        self.rng = rng
        steps = np.arange(params.beams, dtype=np.float64)
        self._beam_angles: FloatArray = params.angle_min + params.angle_increment * steps

    def scan(self, x: float, y: float, yaw: float, moving: StaticGeometry | None = None) -> FloatArray:
        """Ranges (beams,) (m) from a sensor at (x, y) facing ``yaw`` (rad), map frame.

        ``moving``: obstacles placed for this scan only (other robots, a handful of shapes), each beam
        tested against each (lidar_jit.cast_each; cast_rays with the reference caster), merged beam by
        beam with the static geometry's ranges. Why apart: the compiled caster files its geometry into
        bins once; re-filing a large world because a robot moved would cost more than the scan.
        """
        p = self.params
        angles, reach = self._beam_angles + yaw, p.range_max + 4.0 * p.noise_stddev
        true = self._cast((x, y), angles, self.geometry, reach)
        if moving is not None:
            true = np.minimum(true, self._cast_moving((x, y), angles, moving, reach))
        measured = true + self.rng.normal(0.0, p.noise_stddev, p.beams) if p.noise_stddev > 0 else true.copy()
        measured[measured > p.range_max] = np.inf
        measured[measured < p.range_min] = -np.inf
        if p.dropout_probability > 0.0:
            measured[self.rng.random(p.beams) < p.dropout_probability] = np.inf
        return measured
