"""cl_ros2_timer: ``ClRos2Timer``, ``CbTimer`` and the countdown behaviors posting ``EvTimer[Cb, Or]``.

SMACC2's semantics, which this client keeps: ``ClRos2Timer(duration, oneshot=False)`` ticks every
``duration`` for the machine's whole life (and posts ``EvTimer[ClRos2Timer, Or]`` on each tick);
``CbTimer`` posts ``EvTimer[CbTimer, Or]`` on every tick while its state is active;
``CbTimerCountdownOnce(n)`` and ``CbTimerCountdownLoop(n)`` count ``n`` *ticks of the client* from the
state's entry and post ``EvTimer[Cb, Or]`` at the n-th (once) or every n-th (loop). So a literal port,
``ClRos2Timer(0.5)`` and ``CbTimerCountdownOnce(40)``, waits 40 ticks = 20 s, as in C++.

An addition: a countdown given a float counts seconds on a timer of its own, and needs no tick
period (``CbTimerCountdownOnce(15.0)``: 15 s after entry). The type decides, as ``int`` is SMACC2's
``triggerTickCount``; an integer tick count on an orthogonal whose ClRos2Timer has no tick period is
refused when the machine initializes, with a message saying what SMACC2's call means and both ways
to write it here.

Timers run on the node clock, so under ``use_sim_time`` a tick is simulated time. They are
``ros_tools.runtime.timers`` periodic timers: rclpy's EventsExecutor can deliver one timer event several
times, and a plain timer would then tick a countdown more than once at one sim time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from datetime import timedelta
from typing import Any

from ros_tools.runtime.timers import create_periodic_timer, destroy_periodic_timer
from smacc_py.core import EvTimer, ISmaccClient, SmaccClientBehavior, SmaccError
from smacc_py.core.client import OrthogonalPort
from smacc_py.ros.components.signal import SmaccSignal
from smacc_py.ros.context import ros_context

#: What a duration may be: seconds (float or int), a ``datetime.timedelta``, or anything with an int
#: ``nanoseconds`` (``rclpy.duration.Duration``, the Python side of SMACC2's ``rclcpp::Duration``).
DurationArg = Any


def duration_seconds(owner: str, duration: DurationArg) -> float:
    """``duration`` in seconds, > 0 and finite; TypeError/ValueError naming ``owner`` otherwise."""
    if isinstance(duration, timedelta):
        seconds = duration.total_seconds()
    elif isinstance(getattr(duration, "nanoseconds", None), int):
        seconds = duration.nanoseconds * 1e-9
    elif isinstance(duration, (int, float)) and not isinstance(duration, bool):
        seconds = float(duration)
    else:
        raise TypeError(f"{owner}: a duration is seconds, a timedelta or an rclpy Duration, got {duration!r}")
    if not (seconds > 0.0 and math.isfinite(seconds)):
        raise ValueError(f"{owner}: the duration must be > 0 s and finite, got {duration!r}")
    return seconds


class ClRos2Timer(ISmaccClient):
    """A node-clock timer ticking every ``duration`` (SMACC2's ``ClRos2Timer(rclcpp::Duration, oneshot)``).

    Args:
        duration: tick period (s, timedelta or rclpy Duration); None: no ticks, only float countdowns.
        oneshot: tick once, ``duration`` after the machine started, then never again.

    Attributes:
        ticks: ticks so far.
        on_timer_tick: signal emitting the tick number on every tick (executor thread).
    """

    def __init__(self, duration: DurationArg | None = None, oneshot: bool = False) -> None:
        self.period_s = None if duration is None else duration_seconds(type(self).__name__, duration)
        self.oneshot = oneshot
        self.ticks = 0
        self.on_timer_tick: SmaccSignal[int] = SmaccSignal(f"{type(self).__name__}.on_timer_tick")
        self._tick_timer: Any = None

    def on_initialize(self) -> None:
        if self.period_s is not None:
            self._tick_timer = self.create_timer(self.period_s, self._on_tick)

    def _on_tick(self) -> None:
        if self.oneshot and self.ticks:
            return
        self.ticks += 1
        if self.oneshot:
            self._tick_timer.cancel()
        self.on_timer_tick.emit(self.ticks)
        self.post_event(self.own_event(EvTimer)(count=self.ticks))

    def create_timer(self, period_s: float, callback: Callable[[], None]) -> Any:
        """A node timer (node clock) calling ``callback`` every ``period_s`` s on the executor, once per
        period however often the executor delivers its event."""
        return create_periodic_timer(ros_context(self.sm).node, period_s, callback)

    def destroy_timer(self, timer: Any) -> None:
        """Stop and destroy a timer made by ``create_timer``."""
        timer.cancel()
        destroy_periodic_timer(ros_context(self.sm).node, timer)


def _tick_problem(behavior: str, orthogonal: OrthogonalPort, ticks: int | None) -> str | None:
    """Why ``behavior`` counting ``ticks`` (None: every tick) cannot run on ``orthogonal``, or None."""
    client = orthogonal.get_client(ClRos2Timer)
    what = "every tick" if ticks is None else f"{ticks} ticks"
    call = f"{behavior}()" if ticks is None else f"{behavior}({ticks})"
    if client is None:
        return f"{call} counts {what} of a ClRos2Timer, and the orthogonal has none"
    if client.period_s is not None:
        return None
    cl = type(client).__name__
    seconds = "" if ticks is None else f", or count seconds with a float ({behavior}({ticks}.0))"
    return (f"{call} counts {what} of the orthogonal's {cl}, as in SMACC2, but that client has no tick "
            f"period: create it with one (create_client({cl}, 0.5) ticks every 0.5 s){seconds}")


class CbTimer(SmaccClientBehavior):
    """Posts ``EvTimer[CbTimer, Or]`` on every tick of the orthogonal's ClRos2Timer (SMACC2's CbTimer)."""

    @classmethod
    def configuration_problem(cls, orthogonal: OrthogonalPort, args: tuple[Any, ...],
                              kwargs: Mapping[str, Any]) -> str | None:
        return _tick_problem(cls.__name__, orthogonal, None)

    def on_entry(self) -> None:
        self._disconnect = self.requires_client(ClRos2Timer).on_timer_tick.connect(self._on_tick)

    def _on_tick(self, tick: int) -> None:
        self.post_event(self.own_event(EvTimer)(count=tick))

    def on_exit(self) -> None:
        self._disconnect()


class _CbTimerCountdown(SmaccClientBehavior):
    once = True

    def __init__(self, ticks_or_duration_s: int | float) -> None:
        name = type(self).__name__
        self.tick_count: int | None = None
        self.duration_s: float | None = None
        if isinstance(ticks_or_duration_s, bool) or not isinstance(ticks_or_duration_s, (int, float)):
            raise TypeError(f"{name}: expected a tick count (int) or a duration in seconds (float), got "
                            f"{ticks_or_duration_s!r}")
        if isinstance(ticks_or_duration_s, int):
            if ticks_or_duration_s < 1:
                raise ValueError(f"{name}: the tick count must be >= 1, got {ticks_or_duration_s}")
            self.tick_count = ticks_or_duration_s
        else:
            self.duration_s = duration_seconds(name, ticks_or_duration_s)
        self.fired = 0

    @classmethod
    def configuration_problem(cls, orthogonal: OrthogonalPort, args: tuple[Any, ...],
                              kwargs: Mapping[str, Any]) -> str | None:
        count = args[0] if args else kwargs.get("ticks_or_duration_s")
        if isinstance(count, int) and not isinstance(count, bool):
            return _tick_problem(cls.__name__, orthogonal, count)
        return None

    def on_entry(self) -> None:
        self._client = self.requires_client(ClRos2Timer)
        self._ticks_seen = 0
        self._timer: Any = None
        self._disconnect: Callable[[], None] | None = None
        if self.tick_count is None:
            assert self.duration_s is not None
            self._timer = self._client.create_timer(self.duration_s, self._fire)
            return
        if self._client.period_s is None:  # configuration_problem refuses this at startup already
            raise SmaccError(_tick_problem(type(self).__name__, self.orthogonal, self.tick_count))
        self._disconnect = self._client.on_timer_tick.connect(self._on_tick)

    def _on_tick(self, _tick: int) -> None:
        self._ticks_seen += 1
        assert self.tick_count is not None
        if self._ticks_seen % self.tick_count == 0:
            self._fire()

    def _fire(self) -> None:
        if self.once and self.fired:
            return
        self.fired += 1
        if self.once:
            self._stop()
        self.post_event(self.own_event(EvTimer)(count=self.fired))

    def _stop(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
        if self._disconnect is not None:
            self._disconnect()
            self._disconnect = None

    def on_exit(self) -> None:
        self._stop()
        if self._timer is not None:
            self._client.destroy_timer(self._timer)
            self._timer = None


class CbTimerCountdownOnce(_CbTimerCountdown):
    """Posts ``EvTimer[CbTimerCountdownOnce, Or]`` once: after ``n`` client ticks (int, SMACC2) or
    ``seconds`` of node clock (float) from entry."""


class CbTimerCountdownLoop(_CbTimerCountdown):
    """Posts ``EvTimer[CbTimerCountdownLoop, Or]`` every ``n`` client ticks (int, SMACC2) or every
    ``seconds`` of node clock (float) while active."""

    once = False


__all__ = ["CbTimer", "CbTimerCountdownLoop", "CbTimerCountdownOnce", "ClRos2Timer", "duration_seconds"]
