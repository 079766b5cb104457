"""Sim-time periodic timers called by their clock (ros_tools/runtime/clock_timers.py).

The clock's move to time T makes every call due at or before T, oldest slot first, on rcl's grid
and with rcl's catch-up rule; no executor holds these timers, so none can repeat, lose or reorder a
call (the EventsExecutor's faults the module names). Each check moves a node's sim clock by hand, as
its TimeSource does on /clock.
"""

from __future__ import annotations

import gc
import weakref
from collections.abc import Iterator
from typing import Any

import pytest
from rclpy.experimental.events_executor import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.time import Time

from ros_tools.runtime import timers
from ros_tools.runtime.clock_timers import ClockTimer

pytestmark = pytest.mark.ros
MS = 1_000_000
SIM_TIME = [Parameter("use_sim_time", value=True)]


@pytest.fixture
def node(ros_context: Any) -> Iterator[Node]:
    probe = Node("clock_timer_probe", context=ros_context, parameter_overrides=SIM_TIME)
    yield probe
    probe.destroy_node()


def _set(node: Node, ms: int) -> None:
    clock: Any = node.get_clock()
    clock.set_ros_time_override(Time(nanoseconds=ms * MS, clock_type=clock.clock_type))


def test_timers_on_sim_time_are_clock_driven_and_no_executor_holds_them(node: Node) -> None:
    timer = timers.create_periodic_timer(node, 0.05, lambda: None)
    assert isinstance(timer, ClockTimer)
    assert all(timer is not held for held in node.timers)


def test_a_tick_calls_due_timers_oldest_slot_first_then_by_creation(node: Node) -> None:
    order: list[str] = []
    _set(node, 0)
    timers.create_periodic_timer(node, 0.03, lambda: order.append("a"))   # slots 30, 60, 90
    timers.create_periodic_timer(node, 0.02, lambda: order.append("b"))   # slots 20, 40, 60
    timers.create_periodic_timer(node, 0.06, lambda: order.append("c"))   # slot 60
    _set(node, 20)
    assert order == ["b"]
    _set(node, 60)  # a jump over 30 and 40: a at 30 and b at 40, then the slot-60 calls by creation
    assert order == ["b", "a", "a", "b", "b", "c"]


def test_catch_up_follows_rcl(node: Node) -> None:
    """rcl_timer_call: one period on; a timer further behind skips to the first slot ahead."""
    calls: list[int] = []
    _set(node, 0)
    timer = timers.create_periodic_timer(node, 0.1, lambda: calls.append(node.get_clock().now().nanoseconds))
    _set(node, 200)   # slots 100 and 200 both reached: after the first call the next slot is exactly now
    assert len(calls) == 2
    _set(node, 450)   # slot 300 reached, 400 too: one call, then the first slot ahead, 500
    assert len(calls) == 3
    assert timer.time_until_next_call() == 50 * MS


def test_cancel_reset_destroy_and_a_backward_jump(node: Node) -> None:
    calls: list[int] = []
    _set(node, 1000)
    timer = timers.create_periodic_timer(node, 0.1, lambda: calls.append(1))
    timer.cancel()
    _set(node, 1200)
    assert calls == [] and timer.time_until_next_call() is None
    timer.reset()                                   # one period from now, as rcl_timer_reset
    assert timer.time_until_next_call() == 100 * MS
    _set(node, 1300)
    assert calls == [1]
    _set(node, 500)                                 # backwards: the grid starts again a period on
    assert timer.time_until_next_call() == 100 * MS and calls == [1]
    _set(node, 600)
    assert calls == [1, 1]
    timers.destroy_periodic_timer(node, timer)
    _set(node, 2000)
    assert calls == [1, 1] and timers.earliest_due_ns(node.context) is None


def test_a_callback_may_cancel_a_later_timer_of_the_same_tick(node: Node) -> None:
    calls: list[str] = []
    _set(node, 0)

    def cancel_the_second() -> None:
        calls.append("first")
        second.cancel()

    first = timers.create_periodic_timer(node, 0.1, cancel_the_second)
    second = timers.create_periodic_timer(node, 0.1, lambda: calls.append("second"))
    _set(node, 100)
    assert calls == ["first"]
    first.cancel()


def test_a_destroyed_node_s_timers_owe_nothing(ros_context: Any) -> None:
    probe = Node("doomed_timer_probe", context=ros_context, parameter_overrides=SIM_TIME)
    _set(probe, 0)
    timers.create_periodic_timer(probe, 0.1, lambda: None)
    assert timers.earliest_due_ns(ros_context) == 100 * MS
    probe.destroy_node()
    assert timers.earliest_due_ns(ros_context) is None


def test_a_destroyed_node_with_sim_time_timers_is_freed_with_its_participant(ros_context: Any) -> None:
    """Nothing of this module keeps a destroyed node: a registry of drivers kept every node that ever
    had a sim-time timer, and with it its DDS participant (CI runs 18 and 19: about thirty in one test
    worker, after which localhost discovery found no new process)."""
    probe = Node("freed_timer_probe", context=ros_context, parameter_overrides=SIM_TIME)
    _set(probe, 0)
    timers.create_periodic_timer(probe, 0.1, lambda: None)
    timers.create_periodic_timer(probe, 0.2, probe.get_name)  # a callback that holds the node itself
    gone = weakref.ref(probe)
    probe.destroy_node()
    del probe
    gc.collect()
    assert gone() is None


def test_a_paused_clock_gives_the_executor_nothing_to_do(node: Node) -> None:
    """The stall this replaces: on a clock that stands still, a due 20 Hz timer made rclpy's
    EventsExecutor queue dispatch after dispatch. Here the executor has no timer to dispatch."""
    calls: list[int] = []
    _set(node, 0)
    timers.create_periodic_timer(node, 0.05, lambda: calls.append(1))
    _set(node, 50)
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    try:
        for _ in range(20):
            executor.spin_once(timeout_sec=0.01)
    finally:
        executor.shutdown()
    assert calls == [1]
