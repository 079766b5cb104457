"""``ExecutorDispatch``: the machine's events are dispatched on the executor thread, never elsewhere.

Why: with one thread running every ROS callback, every transition, every hook and every
ISmaccUpdatable poll, nothing needs a lock, no callback waits for another thread, and the order in
which a machine sees its events follows the order in which the executor ran the callbacks that
posted them, not the timing of a second thread. So the same inputs give the same states however
busy the machine is.

How: the engine runs in its synchronous mode and calls ``request()`` after every post.

* A post from an executor callback schedules one drain (``sm.process_events()``) with
  ``executor.create_task``. Both of rclpy's executors run a task created by a callback right after
  that callback, before messages that arrived meanwhile.
* A post from another thread (an async behavior's ``on_entry``) goes the same way:
  ``create_task`` is thread-safe and wakes the spinning thread (about 65 µs here).
* At most one drain is pending at a time (posts coalesce), and a post made while a drain or
  ``dispatch_after`` runs on the executor thread schedules nothing: that drain picks it up.

The flag that coalesces is cleared before the drain starts, so a post from another thread during
a drain either lands in the queue before the drain empties it or schedules the next drain: no event
is ever left waiting.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

from smacc_py.core import SmaccStateMachineBase

_log = logging.getLogger("smacc_py")


class ExecutorDispatch:
    """Dispatches ``sm``'s events on ``executor``'s spinning thread (see the module docstring).

    Args:
        sm: a machine in synchronous mode (``start()``, not ``start(threaded=True)``).
        executor: an rclpy executor (EventsExecutor or SingleThreadedExecutor) that spins its node.
    """

    def __init__(self, sm: SmaccStateMachineBase, executor: Any) -> None:
        self.sm = sm
        self.executor = executor
        self._lock = threading.Lock()
        self._pending = False  # a drain task is scheduled and has not started
        self._closed = False
        self._busy_thread: int | None = None  # the executor thread, while it will drain before returning
        self.drains = 0  # drains run (tests and benchmarks read it)
        sm.set_wake_callback(self.request)

    def request(self) -> None:
        """Make sure the queued events get dispatched on the executor thread soon (any thread)."""
        if self._closed or self._busy_thread == threading.get_ident():
            return
        with self._lock:
            if self._pending:
                return
            self._pending = True
        self.executor.create_task(self._run_task)

    def dispatch_after(self, work: Callable[[], None]) -> None:
        """On the executor thread: run ``work`` (enter the initial state, poll the updatables), then
        dispatch the events it posted, before this callback returns."""
        if self._busy_thread is not None:  # nested: the outer call dispatches
            work()
            return
        self._busy_thread = threading.get_ident()
        try:
            work()
            self._drain()
        finally:
            self._busy_thread = None

    def close(self) -> None:
        """Schedule nothing more (shutdown); the machine stays as it is."""
        self._closed = True
        self.sm.set_wake_callback(None)

    def _run_task(self) -> None:
        with self._lock:
            self._pending = False
        self.dispatch_after(_nothing)

    def _drain(self) -> None:
        if self._closed or not self.sm.is_running:
            return
        self.drains += 1
        try:
            self.sm.process_events()
        except Exception:  # the engine logs the faults of user hooks itself; this is a last resort
            _log.exception("%s: dispatching events raised", self.sm.name)


def _nothing() -> None:
    """The work of a drain task: none besides the drain itself."""
