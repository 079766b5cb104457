"""Say when a process's executor falls behind: a stuck callback, or a queue it no longer keeps up with.

Why: a process whose executor stops turning stops everything at once, silently. Its timers do not
fire, its lockstep reports stop (the simulator then drops it after ``lockstep.timeout``), and a
state machine waits forever in the state it was in. CI once saw exactly that (SmNav2Test1 silent
for 10 s at a time, seven times in a 600 s run) and had nothing to tell why. This watch makes such a
process say so itself, with what its executor thread is doing.

How: a daemon thread hands the executor a no-op task (``executor.create_task``, thread-safe in both
of rclpy's executors) every ``period`` s of wall time and times how long the task waits for its
turn. A task still waiting after ``threshold`` s means the executor is ``threshold`` s behind: one
callback has held its thread that long, or the events queued ahead of the task take that long to
run. One warning names the lag and the executor thread's Python stack (the callback it is in, or
``spin_once`` when it is working through a queue); one line says when it caught up, and after
how long. Nothing is printed while the executor keeps up. Wall-clock times throughout: the question
is whether the process keeps up with the world, not with its own clock.
"""

from __future__ import annotations

import logging
import sys
import threading
import time
import traceback
from typing import Any

_log = logging.getLogger("ros_tools.executor_watch")

PERIOD_S = 1.0  # wall s between two probes
THRESHOLD_S = 3.0  # wall s a probe may wait before the executor counts as behind


class ExecutorWatch:
    """Probes ``executor`` from a daemon thread (see the module docstring).

    Args:
        executor: an rclpy executor (EventsExecutor or SingleThreadedExecutor).
        name: the process or machine the warnings name (``SmNav2Test1``, ``nav2``).
        logger: where the warnings go (a node's logger, or ``logging``); ``warning`` and ``info`` are used.
        period, threshold: wall seconds between probes, and a probe's wait that counts as falling behind.
    """

    def __init__(self, executor: Any, name: str, logger: Any = None, period: float = PERIOD_S,
                 threshold: float = THRESHOLD_S) -> None:
        self.executor = executor
        self.name = name
        self.logger = logger if logger is not None else _log
        self.period = period
        self.threshold = threshold
        self.spinning_thread: int | None = None  # ident of the thread in spin_once, for the stack
        self.worst_lag = 0.0  # wall s the slowest probe waited (tests and benchmarks read it)
        self.stalls = 0  # times the executor fell behind by more than ``threshold``
        self._sent_at: float | None = None  # wall time the probe in flight was created
        self._warned = False
        self._stop = threading.Event()
        self._stop.set()  # not watching until start()

    def start(self) -> ExecutorWatch:
        """Watch from a new daemon thread (nothing when already watching); again after stop()."""
        if self._stop.is_set():
            self._stop = threading.Event()
            threading.Thread(target=self._run, args=(self._stop,), name=f"{self.name}.executor_watch",
                             daemon=True).start()
        return self

    def stop(self) -> None:
        """End the watch thread (returns at once; the thread ends within ``period``)."""
        self._stop.set()

    def _run(self, stop: threading.Event) -> None:
        while not stop.wait(self.period):
            sent = self._sent_at
            if sent is None:
                self._send()
                continue
            waited = time.monotonic() - sent
            if waited > self.threshold and not self._warned:
                self._warned = True
                self.stalls += 1
                self.logger.warning(
                    f"{self.name}: the executor is {waited:.1f} s (wall) behind: nothing queued since then "
                    f"has run (timers, messages, lockstep reports). Its thread is at:\n{self._stack()}")

    def _send(self) -> None:
        self._sent_at = time.monotonic()
        try:
            self.executor.create_task(self._arrived)
        except Exception:  # the executor was shut down: nothing left to watch
            self.stop()

    def _arrived(self) -> None:
        sent = self._sent_at
        if sent is None:
            return
        lag = time.monotonic() - sent
        self.worst_lag = max(self.worst_lag, lag)
        self._sent_at = None
        if self._warned:
            self._warned = False
            self.logger.info(f"{self.name}: the executor caught up after {lag:.1f} s (wall)")

    def _stack(self) -> str:
        thread = self.spinning_thread
        frame = sys._current_frames().get(thread) if thread is not None else None
        if frame is None:
            return "  (the executor thread is not known or not running)"
        return "".join(traceback.format_stack(frame)[-12:]).rstrip()
