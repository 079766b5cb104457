"""Replays rclpy timer deliveries by hand, as an executor makes each one.

Why: rclpy's EventsExecutor can deliver one timer event several times (ros_tools/runtime/timers.py);
tests replay such a burst deterministically instead of waiting for the executor to make one.
"""

from __future__ import annotations

import time
from typing import Any


def wait_until_due(timer: Any, limit_s: float = 5.0) -> None:
    """Return once ``timer`` is due; AssertionError after ``limit_s`` wall seconds (a safety net)."""
    deadline = time.monotonic() + limit_s
    while not timer.is_ready():
        if time.monotonic() > deadline:
            raise AssertionError("the timer never became due")
        time.sleep(0.01)


def next_call_ns(timer: Any) -> int:
    """When the timer calls next (ns on its clock)."""
    return int(timer.clock.now().nanoseconds + timer.time_until_next_call())


def deliver(timer: Any) -> None:
    """One delivery of the timer's ready event: rcl's timer call (which moves the next call a period
    on, due or not), then the Python callback."""
    with timer.handle:
        timer.handle.call_timer()
    timer.callback()
