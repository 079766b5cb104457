"""``FirstClock``: run a function on the executor thread as soon as the node clock is valid.

Why: under ``use_sim_time`` the node clock reads 0 until the first /clock message. A machine that
entered its initial state then would arm its timers at t = 0, and they would all fire at once when
the clock jumps to the simulation's time. So the runtime enters the initial state right after the
first /clock message, and no thread sits polling the clock for it:

* the clock is already valid (wall time, or /clock seen before ``arm()``): the function runs in the
  next executor turn;
* else a clock jump callback (rclpy calls it from the time source's /clock subscription, on the
  executor thread) schedules the function with ``executor.create_task``, which runs it right after
  that /clock callback. It is not run inside the jump callback itself: creating timers there would
  modify the clock's jump callbacks while rcl iterates over them.

A steady (wall) timer logs once, after ``NOTICE_AFTER_S``, that the machine is waiting for /clock.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rclpy.clock import Clock, ClockType, JumpHandle, JumpThreshold
from rclpy.duration import Duration
from rclpy.node import Node

NOTICE_AFTER_S = 2.0  # wall s without a valid clock before the "waiting for /clock" log line


class FirstClock:
    """Calls ``on_valid()`` once, on the executor thread, when ``node``'s clock first reads > 0."""

    def __init__(self, node: Node, executor: Any, on_valid: Callable[[], None]) -> None:
        self.node = node
        self.executor = executor
        self.on_valid = on_valid
        self.fired = False
        self._armed = False
        self._closed = False
        self._jump: JumpHandle | None = None
        self._notice: Any = None

    def arm(self) -> None:
        """Start watching (from any thread; the check runs on the executor thread)."""
        if self._armed:
            return
        self._armed = True
        self.executor.create_task(self._check)

    def close(self) -> None:
        """Stop watching and release the jump callback and the notice timer (executor thread, or
        after spinning stopped)."""
        self._closed = True
        self._release()

    def _valid(self) -> bool:
        return self.node.get_clock().now().nanoseconds > 0

    def _check(self) -> None:
        if self._closed or self.fired:
            return
        if self._valid():
            self.fired = True
            self._release()
            self.on_valid()
            return
        if self._jump is None:
            threshold = JumpThreshold(min_forward=Duration(nanoseconds=1), min_backward=None,
                                      on_clock_change=True)
            self._jump = self.node.get_clock().create_jump_callback(threshold, post_callback=self._on_jump)
            self._notice = self.node.create_timer(
                NOTICE_AFTER_S, self._log_waiting, clock=Clock(clock_type=ClockType.STEADY_TIME))

    def _on_jump(self, _jump: Any) -> None:
        if not self._closed and not self.fired and self._valid():
            self.executor.create_task(self._check)

    def _log_waiting(self) -> None:
        if self._notice is not None:
            self._notice.cancel()
        if not self.fired:
            self.node.get_logger().info("use_sim_time is true: waiting for /clock before starting")

    def _release(self) -> None:
        if self._jump is not None:
            self._jump.unregister()
            self._jump = None
        if self._notice is not None:
            self.node.destroy_timer(self._notice)
            self._notice = None
