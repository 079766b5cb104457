"""ros_tools.runtime.offload over rclpy: work on a worker thread, its result on the executor's.

A coroutine awaits an offloaded job while the executor keeps serving a timer (it is not blocked),
the result and an exception come back on the executor thread, jobs run one at a time in order, and
destroy() ends what was not handed back with OffloadClosedError.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import pytest
from rclpy.node import Node

from navsuite_testing.ros import spin_until
from ros_tools.runtime.coroutines import spawn, until
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.offload import Offload, OffloadClosedError

pytestmark = pytest.mark.ros


@pytest.fixture(params=["events", "single"])
def rig(request: Any, ros_context: Any) -> Any:
    node = Node("offload_test", context=ros_context)
    executor = make_executor(request.param, context=ros_context)
    executor.add_node(node)
    offload = Offload(node, "test_worker")
    try:
        yield node, executor, offload
    finally:
        offload.destroy()
        executor.shutdown()
        node.destroy_node()


def test_a_job_runs_on_the_worker_while_the_executor_serves_a_timer(rig: Any) -> None:
    node, executor, offload = rig
    executor_thread: list[int] = []
    ticks: list[float] = []
    node.create_timer(0.01, lambda: ticks.append(time.monotonic()))
    release = threading.Event()

    def job(x: int) -> tuple[int, int]:
        release.wait(5.0)  # held until the test has seen the executor serve the timer meanwhile
        return x * 2, threading.get_ident()

    async def main() -> tuple[tuple[int, int], int]:
        executor_thread.append(threading.get_ident())
        value = await until(offload.submit(job, 21))
        return value, threading.get_ident()

    outcome = spawn(node, main())
    spin_until(executor, lambda: len(ticks) >= 5, 10.0, "five timer ticks while the job runs")
    assert not outcome.done()
    release.set()
    spin_until(executor, outcome.done, 10.0, "the job's result")
    (doubled, worker), resumed_on = outcome.result()
    assert doubled == 42
    assert worker != executor_thread[0]           # computed off the executor thread
    assert resumed_on == executor_thread[0]       # and handed back on it


def test_an_exception_comes_back_and_jobs_run_in_order(rig: Any) -> None:
    _node, executor, offload = rig
    order: list[int] = []

    def fail() -> None:
        raise ValueError("no plan")

    answers = [offload.submit(order.append, k) for k in range(5)]
    failed = offload.submit(fail)
    spin_until(executor, lambda: failed.done() and all(a.done() for a in answers), 10.0, "six jobs")
    assert order == [0, 1, 2, 3, 4]
    assert isinstance(failed.exception(), ValueError)


def test_destroy_answers_what_was_not_handed_back(rig: Any) -> None:
    _node, _executor, offload = rig
    running = threading.Event()
    release = threading.Event()

    def slow() -> None:
        running.set()
        release.wait(5.0)

    first = offload.submit(slow)
    queued = offload.submit(lambda: 1)
    assert running.wait(5.0)
    threading.Timer(0.1, release.set).start()
    offload.destroy()
    assert isinstance(queued.exception(), OffloadClosedError)
    assert isinstance(first.exception(), OffloadClosedError)  # ended while destroy() waited
