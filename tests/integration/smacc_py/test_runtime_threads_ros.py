"""SmaccRuntime runs every callback and every event dispatch on its one executor thread.

SmThreads records ``threading.get_ident()`` wherever user code runs: a client's subscription
callback, a sync behavior's ``on_entry``, a node-clock timer, an ISmaccUpdatable poll, a transition
guard, states' ``on_entry`` and ``on_exit``, and the ``on_entry`` of an async behavior, whose own
thread posts the event that ends the machine. Everything but that ``on_entry`` must have run on the
thread that spins the executor, with either executor kind. ``shutdown()`` stops the machine on that
thread too, and the lockstep participant says it leaves.
"""

from __future__ import annotations

import os
import threading
from typing import Any

import pytest
import rclpy
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from std_msgs.msg import Header

from navsuite_testing.ros import spin_until, wait_until
from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC
from smacc_py.core import (
    ISmaccClient,
    ISmaccUpdatable,
    Orthogonal,
    SmaccAsyncClientBehavior,
    SmaccClientBehavior,
    SmaccEvent,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.ros.context import ros_context

pytestmark = pytest.mark.ros

#: where -> idents of the threads user code ran on there (cleared by each test)
SEEN: dict[str, set[int]] = {}


def _seen(where: str) -> None:
    SEEN.setdefault(where, set()).add(threading.get_ident())


def _guard(event: Any) -> bool:
    _seen("guard")
    return True


class EvTick(SmaccEvent):
    """Posted by CbTimed's node-clock timer."""


class EvFromThread(SmaccEvent):
    """Posted by CbAsyncPost from its own thread."""


class ClProbe(ISmaccClient, ISmaccUpdatable):
    """Subscribes /odom (FakeNav2 publishes it at 100 Hz) and records where its callbacks run."""

    def on_initialize(self) -> None:
        self._sub = ros_context(self.sm).node.create_subscription(Odometry, "/odom", self._on_odom, 10)

    def _on_odom(self, msg: Odometry) -> None:
        _seen("subscription")

    def update(self) -> None:
        _seen("update")


class OrProbe(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClProbe)


class CbTimed(SmaccClientBehavior):
    """A sync behavior: records on_entry, then posts EvTick from a 0.2 s node-clock timer."""

    def on_entry(self) -> None:
        _seen("behavior on_entry")
        self._timer = ros_context(self.sm).node.create_timer(0.2, self._on_timer)

    def _on_timer(self) -> None:
        _seen("timer")
        self.post_event(EvTick)

    def on_exit(self) -> None:
        ros_context(self.sm).node.destroy_timer(self._timer)


class CbAsyncPost(SmaccAsyncClientBehavior):
    """An async behavior: posts EvFromThread from its own thread."""

    def on_entry(self) -> None:
        _seen("async on_entry")
        self.post_event(EvFromThread(thread=threading.get_ident()))


class SmThreads(SmaccStateMachineBase):
    initial_state = "StWatch"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrProbe)


class StWatch(SmaccState, parent=SmThreads):
    reactions = [Transition(EvTick, "StAsync")]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrProbe, CbTimed)

    def on_entry(self) -> None:
        _seen("state on_entry")

    def on_exit(self) -> None:
        _seen("state on_exit")


class StAsync(SmaccState, parent=SmThreads):
    reactions = [Transition(EvFromThread, "StDone", guard=_guard)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrProbe, CbAsyncPost)


class StDone(SmaccState, parent=SmThreads):
    def on_entry(self) -> None:
        _seen("state on_entry")

    def on_exit(self) -> None:  # only shutdown() makes the machine leave StDone
        _seen("final on_exit")


def _run_to_done(stack, monkeypatch, executor: str) -> Any:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("NAVSUITE_EXECUTOR", executor)
    SEEN.clear()
    _fake, runtime = stack(SmThreads)
    wait_until(lambda: runtime.sm.current_state_names() == ["StDone"], 20.0, "SmThreads to reach StDone")
    wait_until(lambda: "update" in SEEN and "subscription" in SEEN, 10.0, "a poll and an /odom message")
    assert type(runtime.executor).__name__ == ("EventsExecutor" if executor == "events"
                                               else "SingleThreadedExecutor")
    return runtime


@pytest.mark.parametrize("executor", ["events", "single"])
def test_callbacks_and_dispatch_run_on_the_executor_thread(stack, monkeypatch, executor: str) -> None:  # type: ignore[no-untyped-def]
    runtime = _run_to_done(stack, monkeypatch, executor)
    spinner = runtime._spinner
    seen = {where: set(idents) for where, idents in SEEN.items() if where != "async on_entry"}
    assert set(seen) == {"subscription", "update", "behavior on_entry", "timer", "guard", "state on_entry",
                         "state on_exit"}
    assert all(idents == {spinner.ident} for idents in seen.values()), (spinner.ident, seen)
    # No thread of the machine besides the executor's (no engine worker, no polling thread) and the
    # watch that times the executor's queue (it hands the executor a no-op task and runs nothing itself).
    ours = sorted(t.name for t in threading.enumerate() if t.name.startswith("SmThreads."))
    assert ours == ["SmThreads.executor", "SmThreads.executor_watch"]


@pytest.mark.parametrize("executor", ["events", "single"])
def test_a_post_from_an_async_behaviors_thread_is_dispatched_on_the_executor(stack, monkeypatch,  # type: ignore[no-untyped-def]
                                                                             executor: str) -> None:
    runtime = _run_to_done(stack, monkeypatch, executor)
    (async_thread,) = SEEN["async on_entry"]
    assert async_thread != runtime._spinner.ident
    last = runtime.sm.transition_log[-1]
    assert (last.source, last.target, last.event.thread) == (StAsync, StDone, async_thread)
    assert SEEN["guard"] == {runtime._spinner.ident}  # the reaction to that post ran on the executor


def test_shutdown_stops_the_machine_on_the_executor_and_leaves_lockstep(stack, ros_context) -> None:  # type: ignore[no-untyped-def]
    SEEN.clear()
    probe = rclpy.create_node("lockstep_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    reports: list[Header] = []
    probe.create_subscription(Header, PROGRESS_TOPIC, reports.append, PROGRESS_QOS)
    try:
        _fake, runtime = stack(SmThreads)
        name = f"SmThreads:{os.getpid()}"
        wait_until(lambda: runtime.sm.current_state_names() == ["StDone"], 20.0, "SmThreads to reach StDone")
        spin_until(executor, lambda: any(r.frame_id == name and r.stamp.sec > 0 for r in reports), 20.0,
                   "a lockstep report of the running machine")
        spinner = runtime._spinner
        runtime.shutdown()
        assert not runtime.sm.is_running and runtime.sm.current_state_names() == []
        assert SEEN["final on_exit"] == {spinner.ident}  # the last state exited on the executor thread
        assert not spinner.is_alive()
        spin_until(executor, lambda: any(r.frame_id == name and r.stamp.sec == 0 for r in reports), 10.0,
                   "the participant's leave message (zero stamp)")
        runtime.shutdown()  # twice is harmless
    finally:
        executor.shutdown()
        probe.destroy_node()
