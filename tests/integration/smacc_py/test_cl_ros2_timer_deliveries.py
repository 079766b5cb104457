"""ClRos2Timer's countdowns tick once per period however often the executor delivers the event.

rclpy's EventsExecutor can deliver one timer event several times (ros_tools/runtime/timers.py). On a
plain timer each delivery ran the callback, so a CbTimerCountdownLoop would count several ticks at one
sim time (sm_dance_bot's StEventCountDown counts five of them to leave).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest
from rclpy.node import Node

from smacc_py.clients.cl_ros2_timer import CbTimerCountdownLoop, ClRos2Timer
from smacc_py.ros.context import RosContext, attach_ros_context
from tests.helpers.timer_delivery import deliver, wait_until_due

pytestmark = pytest.mark.ros


def test_a_countdown_tick_delivered_five_times_counts_once(ros_context: Any) -> None:
    node = Node("cl_ros2_timer_probe", context=ros_context)
    try:
        machine = SimpleNamespace()
        attach_ros_context(machine, RosContext(node))
        client = ClRos2Timer()
        client.sm = machine  # type: ignore[assignment]
        countdown = CbTimerCountdownLoop(0.05)
        posted: list[dict[str, Any]] = []
        countdown.requires_client = lambda _type: client  # type: ignore[assignment,method-assign,return-value]
        countdown.own_event = lambda _template: lambda **payload: payload  # type: ignore[assignment,method-assign]
        countdown.post_event = posted.append  # type: ignore[assignment,method-assign]
        countdown.on_entry()
        timer = countdown._timer
        wait_until_due(timer)
        for _ in range(5):  # one due event, delivered five times
            deliver(timer)
        assert countdown.fired == 1
        assert posted == [{"count": 1}]
        countdown.on_exit()
    finally:
        node.destroy_node()
