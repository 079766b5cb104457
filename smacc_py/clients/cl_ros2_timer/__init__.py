"""cl_ros2_timer: ``ClRos2Timer`` and the countdown behaviors posting ``EvTimer[Cb, Or]``.

Timers run on the node clock, so under ``use_sim_time`` a 15 s countdown is 15 s of simulated time.
They are ``ros_tools.runtime.timers`` periodic timers: rclpy's EventsExecutor can deliver one timer
event several times, and a plain timer would then tick a countdown more than once at one sim time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ros_tools.runtime.timers import create_periodic_timer
from smacc_py.core import EvTimer, ISmaccClient, SmaccClientBehavior
from smacc_py.ros.context import ros_context


class ClRos2Timer(ISmaccClient):
    """Creates node-clock timers for its behaviors (SMACC2's cl_ros2_timer client)."""

    def create_timer(self, period_s: float, callback: Callable[[], None]) -> Any:
        """A node timer (node clock) calling ``callback`` every ``period_s`` s on the executor, once per
        period however often the executor delivers its event."""
        return create_periodic_timer(ros_context(self.sm).node, period_s, callback)

    def destroy_timer(self, timer: Any) -> None:
        """Stop and destroy a timer made by ``create_timer``."""
        timer.cancel()
        ros_context(self.sm).node.destroy_timer(timer)


class _CbTimerCountdown(SmaccClientBehavior):
    once = True

    def __init__(self, duration_s: float) -> None:
        if not duration_s > 0.0:
            raise ValueError(f"{type(self).__name__}: duration must be > 0 s, got {duration_s!r}")
        self.duration_s = float(duration_s)
        self.fired = 0

    def on_entry(self) -> None:
        self._client = self.requires_client(ClRos2Timer)
        self._timer = self._client.create_timer(self.duration_s, self._on_timer)

    def _on_timer(self) -> None:
        if self.once and self.fired:
            return
        self.fired += 1
        if self.once:
            self._timer.cancel()
        self.post_event(self.own_event(EvTimer)(count=self.fired))

    def on_exit(self) -> None:
        self._client.destroy_timer(self._timer)


class CbTimerCountdownOnce(_CbTimerCountdown):
    """Posts ``EvTimer[CbTimerCountdownOnce, Or]`` once, ``duration_s`` s (node clock) after entry."""


class CbTimerCountdownLoop(_CbTimerCountdown):
    """Posts ``EvTimer[CbTimerCountdownLoop, Or]`` every ``duration_s`` s (node clock) while active."""

    once = False


__all__ = ["CbTimerCountdownLoop", "CbTimerCountdownOnce", "ClRos2Timer"]
