"""The viewer's settings, with defaults in one place (the command line only overrides them)."""

from __future__ import annotations

import math
from dataclasses import dataclass

SIM_TIME_MODES = ("auto", "true", "false")


@dataclass(frozen=True)
class ViewerParams:
    """Settings of the viewer node and server.

    Attributes:
        host: address the HTTP server binds; loopback by default so nothing leaves the machine.
        port: TCP port; 0 picks a free one (the URL is printed).
        rate: most updates per second sent to each browser (Hz); layers coalesce in between.
        frame: display frame (RViz's "Fixed Frame"); everything is transformed into it via TF.
        sim_time: "auto" switches the node to /clock time once a /clock publisher appears (so
            clicked poses are stamped in simulation time like RViz with use_sim_time), or "true"/"false".
        robot_radius: footprint radius drawn for poses (m), TurtleBot3 waffle by default.
        max_poses: most poses per path or particle cloud sent to the page (evenly decimated).
        discovery_period: how often the ROS graph is scanned for new topics (s, wall clock).
        keepalive: a stream with no change sends an SSE comment this often (s) to detect closed tabs.
        executor: rclpy executor, ``events`` or ``single`` (None: ``$NAVSUITE_EXECUTOR`` or ``events``).
    """

    host: str = "127.0.0.1"
    port: int = 8080
    rate: float = 10.0
    frame: str = "map"
    sim_time: str = "auto"
    robot_radius: float = 0.22
    max_poses: int = 2000
    discovery_period: float = 1.0
    keepalive: float = 10.0
    executor: str | None = None

    def __post_init__(self) -> None:
        if not 0 <= self.port <= 65535:
            raise ValueError(f"viewer port must be in 0..65535, got {self.port}")
        if not (math.isfinite(self.rate) and 0.0 < self.rate <= 100.0):
            raise ValueError(f"viewer rate must be in (0, 100] Hz, got {self.rate}")
        if self.sim_time not in SIM_TIME_MODES:
            raise ValueError(f"viewer sim_time must be one of {SIM_TIME_MODES}, got {self.sim_time!r}")
        if not self.frame:
            raise ValueError("viewer frame must be a non-empty frame id")
        for name in ("robot_radius", "discovery_period", "keepalive"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"viewer {name} must be > 0, got {getattr(self, name)}")
        if self.max_poses < 2:
            raise ValueError(f"viewer max_poses must be >= 2, got {self.max_poses}")
