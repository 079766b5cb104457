"""A warning when simulated time stops while the node has work waiting on it (the simulator paused).

Why: under ``use_sim_time`` every timer of the stack runs on /clock. When the simulator is paused,
stopped or gone, nothing fails: the goal simply never advances, and neither does any timeout that
would report it, since those count sim time too. Only a wall clock can notice. This watch samples
the node clock on a steady (wall) timer and, while ``busy()`` holds, warns once when sim time has
not moved for ``timeout`` wall seconds, naming the likely cause, and says so again when it resumes.
It never fails a goal: a paused simulation is a legitimate state (a user inspecting the scene).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rclpy.clock import Clock, ClockType

PERIOD_S = 1.0  # s (wall) between samples of the node clock
TIMEOUT_S = 10.0  # s (wall) of still sim time, while busy, before the warning


class ClockWatch:
    """Watch ``node``'s clock while ``busy()``; ``what`` names the waiting work in the warning."""

    def __init__(self, node: Any, busy: Callable[[], bool], what: str, timeout: float = TIMEOUT_S) -> None:
        self.node, self.busy, self.what, self.timeout = node, busy, what, timeout
        self.still_for = 0.0  # s (wall) the node clock has not moved while busy
        self._last_ns: int | None = None
        self._warned = False
        self._timer = node.create_timer(PERIOD_S, self._sample, clock=Clock(clock_type=ClockType.STEADY_TIME))

    def _sample(self) -> None:
        now_ns = self.node.get_clock().now().nanoseconds
        moved = self._last_ns is None or now_ns != self._last_ns
        self._last_ns = now_ns
        if moved or not self.busy():
            if self._warned and moved:
                self.node.get_logger().info(f"/clock runs again after {self.still_for:.0f} s (wall)")
            self.still_for, self._warned = 0.0, False
            return
        self.still_for += PERIOD_S
        if self.still_for >= self.timeout and not self._warned:
            self._warned = True
            self.node.get_logger().warn(
                f"{self.what} waits on simulated time, and /clock has not advanced for "
                f"{self.still_for:.0f} s (wall): is the simulator paused, stopped or gone? "
                "(check: ros2py topic hz /clock)")

    def destroy(self) -> None:
        self.node.destroy_timer(self._timer)
