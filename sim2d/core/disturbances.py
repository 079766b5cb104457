"""Faults injected into a running simulation: a lidar that stops returning, an obstacle dropped in.

Why in the core: a test scenario ("the lidar fails for 3 s", "a box falls onto the path") must
happen at a sim time and give the same world on every run, so both are pure state advanced by the
simulator's own clock (integer ns of sim time), never by the wall clock or the ROS layer.

Lidar dropout, and what it looks like to Nav2: the sensor keeps publishing at its rate, but every
beam reads +inf (REP 117: no return within range), which is what a blinded or failed laser looks
like while its driver still runs (a dirty window, a dead diode, a stalled receiver). Nav2 sees
"nothing in range": AMCL gets no usable beam (our health check counts those updates), the obstacle
layers mark nothing and, with ``inf_is_valid: true`` (config/nav2_params.yaml; Nav2's default is
false, which ignores the beams), clear along every beam, so obstacles seen before are forgotten:
the hazard a blind lidar really poses. TF and odometry go on. A sensor that falls silent instead
(a pulled cable) would stall AMCL's map → odom transform and the costmaps' observation buffers: a
different fault, not this one.

Dropped obstacle: a static circle (x, y, radius, m, map frame) added to the world the lidar sees
and the robot collides with. It is refused when it would overlap the robot's footprint: a body
appearing inside the robot has no physical meaning and would leave it stuck for good.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class DroppedObstacle:
    """A round obstacle placed at runtime: centre (x, y) and radius (m), map frame."""

    x: float
    y: float
    radius: float

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.x, self.y, self.radius)):
            raise ValueError(f"obstacle: x, y and radius must be finite, got {self}")
        if self.radius <= 0.0:
            raise ValueError(f"obstacle: radius must be > 0 m, got {self.radius}")

    def as_row(self) -> list[float]:
        """[cx, cy, r], the row layout of StaticGeometry.circles."""
        return [self.x, self.y, self.radius]


class LidarDropout:
    """When the lidar returns nothing: one window [start, end) of sim time (ns).

    A new dropout replaces the running one (the sensor is down until the latest end asked for), and
    a duration <= 0 ends a running dropout at once, so a user can bring the sensor back early.
    """

    def __init__(self) -> None:
        self._start_ns = 0
        self._end_ns = 0

    def start(self, now_ns: int, duration_s: float) -> None:
        """The lidar returns nothing from ``now_ns`` for ``duration_s`` s of sim time (<= 0: back now)."""
        if not math.isfinite(duration_s):
            raise ValueError(f"lidar dropout: duration must be finite seconds, got {duration_s}")
        self._start_ns = now_ns
        self._end_ns = now_ns + max(0, round(duration_s * 1e9))

    def active(self, now_ns: int) -> bool:
        """True while a scan taken at ``now_ns`` must read no return on every beam."""
        return self._start_ns <= now_ns < self._end_ns

    def remaining(self, now_ns: int) -> float:
        """s of sim time until the lidar returns (0 when it is up)."""
        return max(0, self._end_ns - now_ns) * 1e-9 if self.active(now_ns) else 0.0
