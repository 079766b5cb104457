"""The engine's synchronous mode as the ROS runtime drives it: wake callback, no re-entrant dispatch,
and ExecutorDispatch's one-pending-drain scheduling (with a stand-in executor, no rclpy)."""

from __future__ import annotations

import threading
from collections.abc import Callable

import pytest

from smacc_py.core import SmaccError, SmaccEvent, SmaccState, SmaccStateMachineBase, Transition
from smacc_py.ros.dispatch import ExecutorDispatch


class EvGo(SmaccEvent):
    pass


class EvBack(SmaccEvent):
    pass


class SmPingPong(SmaccStateMachineBase):
    initial_state = "StPing"


class StPing(SmaccState, parent=SmPingPong):
    reactions = [Transition(EvGo, "StPong")]


class StPong(SmaccState, parent=SmPingPong):
    reactions = [Transition(EvBack, "StPing")]


class QueueExecutor:
    """Stands in for an rclpy executor: ``create_task`` queues, ``run_tasks`` runs them in order."""

    def __init__(self) -> None:
        self.tasks: list[Callable[[], None]] = []
        self.lock = threading.Lock()

    def create_task(self, task: Callable[[], None]) -> None:
        with self.lock:
            self.tasks.append(task)

    def run_tasks(self) -> int:
        ran = 0
        while self.tasks:
            with self.lock:
                task = self.tasks.pop(0)
            task()
            ran += 1
        return ran


def test_the_wake_callback_runs_after_every_post_from_any_thread() -> None:
    sm = SmPingPong()
    woken: list[int] = []
    sm.set_wake_callback(lambda: woken.append(threading.get_ident()))
    sm.start()
    sm.post_event(EvGo)
    other = threading.Thread(target=sm.post_event, args=(EvBack,))
    other.start()
    other.join()
    assert woken == [threading.get_ident(), other.ident]
    assert sm.process_events() == 2 and sm.current_state_names() == ["StPing"]
    sm.set_wake_callback(None)
    sm.post_event(EvGo)
    assert len(woken) == 2


def test_process_events_refuses_to_reenter_a_running_dispatch() -> None:
    errors: list[Exception] = []

    class StReenter(SmaccState):
        def on_entry(self) -> None:
            try:
                self.sm.process_events()
            except SmaccError as error:
                errors.append(error)

    class SmReenter(SmaccStateMachineBase):
        initial_state = "StIdle"

    class StIdle(SmaccState, parent=SmReenter):
        reactions = [Transition(EvGo, "StReenter")]

    type("StReenter", (StReenter,), {}, parent=SmReenter)
    sm = SmReenter()
    sm.start()
    sm.post_event(EvGo)
    sm.process_events()
    assert sm.current_state_names() == ["StReenter"]
    assert len(errors) == 1 and "inside a dispatch" in str(errors[0])


def test_posts_coalesce_into_one_pending_drain() -> None:
    sm, executor = SmPingPong(), QueueExecutor()
    dispatch = ExecutorDispatch(sm, executor)
    sm.start()
    sm.post_event(EvGo)
    sm.post_event(EvBack)
    sm.post_event(EvGo)
    assert len(executor.tasks) == 1  # three posts, one drain scheduled
    assert executor.run_tasks() == 1
    assert sm.current_state_names() == ["StPong"] and dispatch.drains == 1
    sm.post_event(EvBack)  # the flag was cleared: a new post schedules the next drain
    assert executor.run_tasks() == 1 and sm.current_state_names() == ["StPing"]


def test_posts_inside_dispatch_after_are_dispatched_before_it_returns() -> None:
    sm, executor = SmPingPong(), QueueExecutor()
    dispatch = ExecutorDispatch(sm, executor)
    dispatch.dispatch_after(sm.start)
    dispatch.dispatch_after(lambda: sm.post_event(EvGo))
    assert sm.current_state_names() == ["StPong"]
    assert executor.tasks == []  # the executor thread was going to drain anyway: nothing scheduled


class SmRelay(SmaccStateMachineBase):
    initial_state = "StStart"


class StStart(SmaccState, parent=SmRelay):
    reactions = [Transition(EvGo, "StRelay")]


class StRelay(SmaccState, parent=SmRelay):
    """Its on_entry (inside the drain) has another thread post EvBack and waits for that post."""

    reactions = [Transition(EvBack, "StEnd")]

    def on_entry(self) -> None:
        poster = threading.Thread(target=self.sm.post_event, args=(EvBack,))
        poster.start()
        poster.join()


class StEnd(SmaccState, parent=SmRelay):
    pass


def test_a_post_from_another_thread_during_a_drain_is_not_lost() -> None:
    sm, executor = SmRelay(), QueueExecutor()
    ExecutorDispatch(sm, executor)
    sm.start()
    sm.post_event(EvGo)
    executor.run_tasks()
    # EvBack arrived from another thread while EvGo was being dispatched: either that drain took it or
    # a second one was scheduled; either way it was dispatched.
    assert [r.key()[:2] for r in sm.transition_log] == [("StStart", "StRelay"), ("StRelay", "StEnd")]


def test_close_schedules_nothing_more() -> None:
    sm, executor = SmPingPong(), QueueExecutor()
    dispatch = ExecutorDispatch(sm, executor)
    sm.start()
    dispatch.close()
    sm.post_event(EvGo)
    assert executor.tasks == []


def test_a_drain_after_the_machine_stopped_does_nothing() -> None:
    sm, executor = SmPingPong(), QueueExecutor()
    ExecutorDispatch(sm, executor)
    sm.start()
    sm.post_event(EvGo)
    sm.stop()
    executor.run_tasks()  # would raise "start() the machine before processing events"
    assert sm.current_state_names() == []


@pytest.mark.parametrize("posts", [1, 5])
def test_posts_from_other_threads_are_all_dispatched(posts: int) -> None:
    sm, executor = SmPingPong(), QueueExecutor()
    ExecutorDispatch(sm, executor)
    sm.start()
    threads = [threading.Thread(target=sm.post_event, args=(EvGo if i % 2 == 0 else EvBack,))
               for i in range(posts)]
    for thread in threads:
        thread.start()
        thread.join()  # in order: the machine must end where the last post leads
    executor.run_tasks()
    assert sm.current_state_names() == ["StPong"]
