"""Long computations off the executor thread, their results back on it as rclpy futures.

Why: one thread runs every callback of a process. A computation that takes tens or hundreds of
milliseconds there (a global plan on a warehouse map) stops everything else for that long: the
controller's 20 Hz cycle, and the cancel request of the very goal being computed, which is only
read once the computation has returned. An :class:`Offload` runs such work on its own worker
thread, one job at a time in submission order, and completes an rclpy future on the executor
thread when a job ends, so a coroutine awaits it with :func:`.coroutines.until`. The worker posts
the hand-back with ``executor.create_task``, which both executors accept from any thread (the
EventsExecutor supports no guard conditions).

A job must not touch ROS entities; it gets plain data (copies) and returns plain data. A job that
should stop early polls a flag its owner sets from a callback (a ``threading.Event``);
:class:`CancelFlags` keeps one per action goal and sets it when the goal's cancel is accepted.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import threading
from collections.abc import Callable, Iterator
from typing import Any

from rclpy.action import CancelResponse
from rclpy.node import Node
from rclpy.task import Future


class OffloadClosedError(RuntimeError):
    """The offload was destroyed before this job's result was handed back."""


class Offload:
    """One worker thread of ``node``'s process, and the hand-back of its results.

    Args:
        node: the node whose executor receives the results (it must be added to one).
        name: the worker thread's name, for stack dumps and profiles.
    """

    def __init__(self, node: Node, name: str) -> None:
        self._node = node
        self._pool = concurrent.futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix=name)
        self._lock = threading.Lock()
        self._pending: list[tuple[concurrent.futures.Future[Any], Future]] = []
        self._closed = False

    def submit(self, job: Callable[..., Any], *args: Any) -> Future:
        """Run ``job(*args)`` on the worker; the returned future completes on the executor thread
        with its result, or with its exception (:class:`OffloadClosedError` if destroyed first)."""
        answer = Future()
        work = self._pool.submit(job, *args)
        with self._lock:
            self._pending.append((work, answer))
        work.add_done_callback(self._wake)
        return answer

    def _wake(self, _work: concurrent.futures.Future[Any]) -> None:
        """Worker thread: post the hand-back to the executor."""
        executor = self._node.executor
        with self._lock:
            if self._closed or executor is None:
                return
        with contextlib.suppress(Exception):  # an executor shut down meanwhile: destroy() answers
            executor.create_task(self._deliver)

    def _deliver(self) -> None:
        """Executor thread: complete the answers of the jobs that ended."""
        with self._lock:
            done = [(work, answer) for work, answer in self._pending if work.done()]
            self._pending = [(work, answer) for work, answer in self._pending if not work.done()]
        for work, answer in done:
            error = OffloadClosedError("the job was dropped") if work.cancelled() else work.exception()
            if error is not None:
                answer.set_exception(error)
            else:
                answer.set_result(work.result())

    def destroy(self) -> None:
        """Drop the queued jobs and wait for the running one (its owner should have asked it to
        stop); every answer not handed back yet ends with :class:`OffloadClosedError`."""
        self._pool.shutdown(wait=True, cancel_futures=True)
        with self._lock:
            self._closed = True
            pending, self._pending = self._pending, []
        for _work, answer in pending:
            answer.set_exception(OffloadClosedError("destroyed before the result was handed back"))


class CancelFlags:
    """One ``threading.Event`` per running action goal, set once a cancel of that goal is accepted:
    what an offloaded job polls to stop early (a goal handle is not for reading from the worker)."""

    def __init__(self) -> None:
        self._flags: dict[bytes, threading.Event] = {}

    @contextlib.contextmanager
    def held(self, handle: Any) -> Iterator[threading.Event]:
        """The flag of ``handle``'s goal while the ``with`` block runs."""
        key = bytes(handle.goal_id.uuid)
        flag = self._flags[key] = threading.Event()
        try:
            yield flag
        finally:
            self._flags.pop(key, None)

    def on_cancel(self, handle: Any) -> CancelResponse:
        """An action server's ``cancel_callback``: accept, and set the goal's flag if it has one."""
        flag = self._flags.get(bytes(handle.goal_id.uuid))
        if flag is not None:
            flag.set()
        return CancelResponse.ACCEPT

    def set_all(self) -> None:
        """Ask every job still running to stop (the node is cleaning up)."""
        for flag in list(self._flags.values()):
            flag.set()
