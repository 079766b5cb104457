"""Wait: succeed once the requested duration has passed (no command is sent).

Jazzy's Wait result names no error constants; an invalid (negative or NaN) duration is refused
with :data:`WAIT_INVALID_DURATION` = 1 and a message rather than silently waiting zero seconds.
"""

from __future__ import annotations

from nav_stack.core.behaviors.base import BehaviorResult

WAIT_INVALID_DURATION = 1


class Wait:
    """``start(duration, now)``; ``step(now)`` returns None while waiting, then a success result."""

    def __init__(self) -> None:
        self._start_time = 0.0
        self._duration = 0.0
        self.time_left = 0.0  # feedback (s)

    def start(self, duration: float, now: float) -> BehaviorResult | None:
        if not duration >= 0.0:
            return BehaviorResult(WAIT_INVALID_DURATION, f"wait duration must be >= 0 s, got {duration}", 0.0)
        self._start_time, self._duration, self.time_left = now, duration, duration
        return None

    def step(self, now: float) -> BehaviorResult | None:
        elapsed = now - self._start_time
        self.time_left = max(self._duration - elapsed, 0.0)
        return BehaviorResult(0, "", elapsed) if elapsed >= self._duration else None
