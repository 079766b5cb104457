"""create_periodic_timer: a timer event delivered more than once runs the callback once.

The EventsExecutor's duplicate deliveries are replayed here by hand, as an executor makes each one:
rcl's timer call (which moves the next call a period on, due or not), then the Python callback.
"""

from __future__ import annotations

from typing import Any

from rclpy.clock import Clock, ClockType
from rclpy.node import Node

from ros_tools.runtime.timers import create_periodic_timer
from tests.helpers.timer_delivery import deliver, next_call_ns, wait_until_due

PERIOD_S = 0.05


def test_a_burst_of_deliveries_runs_the_callback_once_and_keeps_the_timer_on_its_grid(
        ros_context: Any) -> None:
    node = Node("periodic_timer_probe", context=ros_context)
    runs: list[int] = []
    try:
        timer = create_periodic_timer(node, PERIOD_S, lambda: runs.append(1),
                                      clock=Clock(clock_type=ClockType.STEADY_TIME))
        wait_until_due(timer)
        slot_ns = next_call_ns(timer)  # the due call's time on the timer's grid
        for _ in range(5):  # one due event, delivered five times
            deliver(timer)
        assert len(runs) == 1
        # the next call is within a period of the due one, not five periods out
        assert slot_ns < next_call_ns(timer) <= slot_ns + 2 * timer.timer_period_ns
    finally:
        node.destroy_node()


def test_a_plain_timer_shows_the_fault_the_guard_removes(ros_context: Any) -> None:
    """Without the guard, five deliveries run five times and push the next call five periods out."""
    node = Node("plain_timer_probe", context=ros_context)
    runs: list[int] = []
    try:
        timer = node.create_timer(PERIOD_S, lambda: runs.append(1),
                                  clock=Clock(clock_type=ClockType.STEADY_TIME))
        wait_until_due(timer)
        for _ in range(5):
            deliver(timer)
        assert len(runs) == 5
        assert timer.time_until_next_call() > 4 * timer.timer_period_ns
    finally:
        node.destroy_node()
