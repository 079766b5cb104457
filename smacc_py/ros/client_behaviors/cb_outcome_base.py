"""``CbOutcomeBase``: a behavior that ends in exactly one EvCbSuccess or EvCbFailure.

Why a base: every generic waiting behavior (a topic message, a node, an action server, a process,
a service answer, a sleep) has the same shape. It starts something in ``on_entry`` and returns at
once. Then either a callback (executor thread) or the runtime's ISmaccUpdatable polling (``poll``)
decides the outcome, and a timeout on the machine clock (the node clock, so sim time under
``use_sim_time``) turns into a failure. ``finish`` posts at most once, from any thread. Nothing here
blocks, and the polling runs on the executor thread, so a sync behavior is enough.

Subclasses implement ``start`` (and optionally ``poll``, ``stop`` and ``timeout_reason``).
Failures carry ``reason`` (a sentence naming the behavior and the value it waited for).
"""

from __future__ import annotations

import threading
from typing import Any

from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior
from smacc_py.ros.components.checks import check_timeout


class CbOutcomeBase(SmaccClientBehavior, ISmaccUpdatable):
    """One-outcome behavior with an optional ``timeout_s`` (s of machine clock; None: never).

    Attributes:
        succeeded: None while running, then True or False.
        started_s: machine-clock time (s) of ``on_entry``.
    """

    timeout_s: float | None = None
    #: False: fail at the first poll at or after ``timeout_s``; True: only once more than ``timeout_s``
    #: has passed. cl_nav2z's and cl_battery's waits predate this base and keep their strict rule, so a
    #: machine's timing does not change when a poll lands exactly on the deadline.
    strict_timeout: bool = False
    succeeded: bool | None = None
    started_s: float = 0.0

    def set_timeout(self, timeout_s: float | None) -> None:
        """Validate and set ``timeout_s`` (call from ``__init__``)."""
        self.timeout_s = check_timeout(type(self).__name__, "timeout_s", timeout_s)

    def on_entry(self) -> None:
        self._outcome_lock = threading.Lock()
        self.started_s = self.sm.now()
        self.start()

    def start(self) -> None:
        """Start the work (subscribe, send, launch); may call ``finish`` at once."""

    def poll(self) -> None:
        """Check the work on each runtime poll (before the timeout check); may call ``finish``."""

    def stop(self) -> None:
        """Release what ``start`` took (subscriptions, processes); runs on state exit."""

    def timeout_reason(self) -> str:
        """The failure reason when ``timeout_s`` ran out."""
        return f"{type(self).__name__} timed out after {self.timeout_s:g} s"

    @property
    def finished(self) -> bool:
        """True once an outcome was posted."""
        return self.succeeded is not None

    def finish(self, success: bool, **payload: Any) -> bool:
        """Post EvCbSuccess (``success``) or EvCbFailure with ``payload``, once; False if already done."""
        with self._outcome_lock:
            if self.succeeded is not None:
                return False
            self.succeeded = success
        if success:
            self.post_success_event(**payload)
        else:
            self.post_failure_event(**payload)
        return True

    def update(self) -> None:
        """Runtime polling: ``poll``, then the timeout."""
        if self.finished:
            return
        self.poll()
        if self.finished or self.timeout_s is None:
            return
        elapsed_s = self.sm.now() - self.started_s
        if elapsed_s > self.timeout_s or (elapsed_s == self.timeout_s and not self.strict_timeout):
            self.finish(False, reason=self.timeout_reason())

    def on_exit(self) -> None:
        self.stop()
