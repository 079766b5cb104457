"""cl_ros_timer: SMACC2's humble-era timer client, ``ClRosTimer(duration, oneshot=False)``.

The same semantics as ``cl_ros2_timer`` (its Jazzy successor), whose behaviors it shares: the client
ticks every ``duration`` (s, timedelta or rclpy Duration) and posts ``EvTimer[ClRosTimer, Or]``;
``CbTimer`` posts on every tick; ``CbTimerCountdownOnce(n)`` / ``CbTimerCountdownLoop(n)`` count ``n``
ticks from their state's entry, as in C++. Why ticks and not seconds: SMACC2's countdowns take
``unsigned long triggerTickCount`` and the period belongs to the client, so a port of
``createClient<ClRosTimer>(500ms)`` and ``CbTimerCountdownOnce(40)`` must wait 20 s, not 40. Unlike
``ClRos2Timer`` the duration is required, as SMACC2's constructor has no default.
"""

from __future__ import annotations

from smacc_py.clients.cl_ros2_timer import (
    CbTimer,
    CbTimerCountdownLoop,
    CbTimerCountdownOnce,
    ClRos2Timer,
    DurationArg,
)
from smacc_py.core import EvTimer


class ClRosTimer(ClRos2Timer):
    """A node-clock timer ticking every ``duration`` (SMACC2's ``cl_ros_timer::ClRosTimer``)."""

    def __init__(self, duration: DurationArg, oneshot: bool = False) -> None:
        if duration is None:
            raise TypeError("ClRosTimer(duration, oneshot=False): the tick period is required, as in SMACC2")
        super().__init__(duration, oneshot)


__all__ = ["CbTimer", "CbTimerCountdownLoop", "CbTimerCountdownOnce", "ClRosTimer", "EvTimer"]
