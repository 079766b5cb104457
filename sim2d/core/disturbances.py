"""Faults injected into a running simulation: a lidar that stops returning, an obstacle dropped in,
wheels that slip (OdometrySlip) and outputs that fall silent (TopicLoss).

Why in the core: a test scenario ("the lidar fails for 3 s", "a box falls onto the path") must
happen at a sim time and give the same world on every run, so all are pure state advanced by the
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


class _Window:
    """One window [start, end) of sim time (ns); a new one replaces the running one."""

    def __init__(self) -> None:
        self.start_ns = 0
        self.end_ns = 0

    def open(self, now_ns: int, duration_s: float, what: str) -> None:
        if not math.isfinite(duration_s):
            raise ValueError(f"{what}: duration must be finite seconds, got {duration_s}")
        self.start_ns, self.end_ns = now_ns, now_ns + max(0, round(duration_s * 1e9))

    def active(self, now_ns: int) -> bool:
        return self.start_ns <= now_ns < self.end_ns


class OdometrySlip:
    """Wheels that slip: for a window of sim time the odometry integrates ``scale`` times the true motion.

    Why a scale on the increment (translation and rotation alike): a wheel spinning on a wet floor
    turns more than the robot moves (scale > 1), a robot pushed or sliding on ice moves more than its
    wheels turn (scale < 1). Either way the odom frame drifts from the truth at a rate the localizer
    must correct from the scans, which is the fault this models; the random drift of
    sim2d.core.odometry runs on top of it. A duration <= 0 ends a running slip at once.
    """

    def __init__(self) -> None:
        self._window = _Window()
        self.scale = 1.0

    def start(self, now_ns: int, scale: float, duration_s: float) -> None:
        """Odometry sees ``scale`` x the motion from ``now_ns`` for ``duration_s`` s of sim time."""
        if not math.isfinite(scale) or scale < 0.0:
            raise ValueError(f"odometry slip: scale must be a finite number >= 0, got {scale}")
        self._window.open(now_ns, duration_s, "odometry slip")
        self.scale = float(scale)

    def active(self, now_ns: int) -> bool:
        return self._window.active(now_ns)

    def apply(self, now_ns: int, dx: float, dy: float, dyaw: float) -> tuple[float, float, float]:
        """The increment (m, m, rad) the odometry integrates at ``now_ns``."""
        if not self._window.active(now_ns):
            return dx, dy, dyaw
        return dx * self.scale, dy * self.scale, dyaw * self.scale


#: The simulator's robot outputs a topic loss may silence (sim2d.ros.sim_node's topic names; "tf" is the
#: odom -> base_footprint transform). Ground truth and /clock are the harness's, not the robot's.
LOSABLE_TOPICS = ("scan", "odom", "tf", "battery_state")


class TopicLoss:
    """Outputs that publish nothing for a window of sim time: a cable pulled, a driver hung, a network
    partition. Unlike a lidar dropout (messages keep coming, every beam +inf) nothing arrives, so
    consumers see stale data: AMCL and the costmaps stop updating, TF goes old. The simulated world
    runs on; only the messages are lost. A duration <= 0 brings the topic back at once.
    """

    def __init__(self) -> None:
        self._windows: dict[str, _Window] = {}

    def start(self, topic: str, now_ns: int, duration_s: float) -> None:
        """``topic`` (one of LOSABLE_TOPICS) publishes nothing for ``duration_s`` s from ``now_ns``."""
        if topic not in LOSABLE_TOPICS:
            known = ", ".join(LOSABLE_TOPICS)
            raise ValueError(f"topic loss: unknown topic {topic!r}; expected one of {known}")
        self._windows.setdefault(topic, _Window()).open(now_ns, duration_s, f"topic loss of {topic}")

    def lost(self, topic: str, now_ns: int) -> bool:
        """True while a message of ``topic`` stamped ``now_ns`` must not be published."""
        window = self._windows.get(topic)
        return window is not None and window.active(now_ns)
