"""When the launcher starts a dead process again: ROS 2 launch's ``Node(respawn=True, respawn_delay=...)``.

Why: nav2_bringup's ``use_respawn`` restarts a crashed server with the same command and parameters,
and Nav2's lifecycle manager then brings the system back through the bond. A restart loop must not
go on for ever, though: a server that crashes at every start (a bad parameter, a missing file) would
otherwise fill the log with start-ups and hide its own error. ROS 2 launch has no such bound; ours
gives a process up once it has died more than ``max_deaths`` times within ``window`` seconds, says
so once, and the launch then stops as for any required process that died.

Pure (stdlib only): the caller passes the wall time (s, any monotonic origin) into every call.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

#: deaths within RESPAWN_WINDOW s after which a respawning process is given up. Not in ROS 2 launch.
RESPAWN_MAX_DEATHS = 3
RESPAWN_WINDOW = 120.0  # s (wall)


@dataclass(frozen=True)
class Respawn:
    """A process's respawn settings (launch's ``respawn`` and ``respawn_delay``, plus our bound).

    Attributes:
        enabled: start the process again when it exits (launch's ``respawn``).
        delay: s (wall) between its death and the new start (launch's ``respawn_delay``).
        max_deaths: deaths within ``window`` after which it is given up (Not in ROS 2 launch: a
            process that dies at every start must end the launch with its error, not loop).
        window: s (wall) over which deaths are counted.
    """

    enabled: bool = False
    delay: float = 0.0
    max_deaths: int = RESPAWN_MAX_DEATHS
    window: float = RESPAWN_WINDOW

    def __post_init__(self) -> None:
        if self.delay < 0.0:
            raise ValueError(f"respawn delay must be >= 0 s, got {self.delay}")
        if self.max_deaths < 1:
            raise ValueError(f"respawn max_deaths must be >= 1, got {self.max_deaths}")
        if self.window <= 0.0:
            raise ValueError(f"respawn window must be > 0 s, got {self.window}")


@dataclass
class RespawnTracker:
    """Counts one process's deaths and decides what follows each: a restart at a time, or giving up."""

    policy: Respawn
    deaths: deque[float] = field(default_factory=deque)  # wall s of the deaths inside the window

    def died(self, now: float) -> float | None:
        """Record a death at ``now``; the wall time of the restart, or None to give the process up."""
        if not self.policy.enabled:
            return None
        self.deaths.append(now)
        while self.deaths and now - self.deaths[0] > self.policy.window:
            self.deaths.popleft()
        if len(self.deaths) > self.policy.max_deaths:
            return None
        return now + self.policy.delay

    @property
    def count(self) -> int:
        """Deaths inside the window, the last one included."""
        return len(self.deaths)

    def given_up_message(self, name: str, code: int) -> str:
        """The one line that says a process is given up, and why."""
        return (f"{name} died {self.count} times within {self.policy.window:.0f} s (last exit code {code}); "
                f"not respawning it again (the limit is {self.policy.max_deaths} restarts)")
