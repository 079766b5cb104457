"""``CbRetry``: run a behavior again when it fails, up to ``retries`` more times, inside one state.

SMACC2's ``CbRetry<TCbRelativeMotion>`` is a template that re-sends the relative motion goal last
stored in CpOdomTracker. This one takes any behavior type and its arguments and builds a fresh
instance for each attempt: ``configure_orthogonal(OrNav, CbRetry, CbNavigateGlobalPosition, 2.0, 0.0,
retries=3)``. Why inside the state: a self-transition retry re-enters the state, re-running its
other behaviors and needing a counter in global data (sm_nav2_gazebo_test_1); CbRetry keeps it local.

The attempt's EvCbSuccess ends the retry at once with ``EvCbSuccess[CbRetry, Or]`` (its payload plus
``attempts`` and ``behavior``). Its EvCbFailure ends that attempt; at the next runtime poll at least
``retry_delay_s`` s of machine clock later the next attempt starts, and after the last one CbRetry
posts ``EvCbFailure[CbRetry, Or](attempts=..., behavior=..., reason=<the last failure>)``. For an async
behavior, EvCbFinished without a failure first counts as success. Every other event an attempt posts
(EvGoalWaypointReached ...) reaches the machine; the clients' own events (EvActionAborted[ClNav2Z, Or]
...) are posted by the clients and reach it too, once per attempt. The running attempt gets its
ISmaccUpdatable polls through CbRetry, and is exited when the state exits.
"""

from __future__ import annotations

import logging
import math
import threading
from typing import Any

from smacc_py.core import (
    EvCbFailure,
    EvCbFinished,
    EvCbSuccess,
    ISmaccClientBehavior,
    ISmaccUpdatable,
    SmaccClientBehavior,
    SmaccEvent,
)

_log = logging.getLogger("smacc_py")

ATTEMPT_JOIN_S = 5.0  # s an async attempt's on_entry may take to return once it is exited


class CbRetry(SmaccClientBehavior, ISmaccUpdatable):
    """Runs ``behavior_type(*args, **kwargs)`` up to ``1 + retries`` times until one succeeds.

    Attributes:
        attempts: attempts started so far.
        current: the attempt running, None between attempts and after the end.
    """

    def __init__(self, behavior_type: type[ISmaccClientBehavior], *args: Any, retries: int = 3,
                 retry_delay_s: float = 0.0, **kwargs: Any) -> None:
        if not (isinstance(behavior_type, type) and issubclass(behavior_type, ISmaccClientBehavior)):
            raise TypeError(f"CbRetry: behavior_type must be a client behavior class, got {behavior_type!r}")
        if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
            raise ValueError(f"CbRetry: retries must be an int >= 0, got {retries!r}")
        if isinstance(retry_delay_s, bool) or not isinstance(retry_delay_s, (int, float)) or not (
                math.isfinite(retry_delay_s) and retry_delay_s >= 0.0):
            raise ValueError(f"CbRetry: retry_delay_s must be a finite number of seconds >= 0, got "
                             f"{retry_delay_s!r}")
        self.behavior_type, self.args, self.kwargs = behavior_type, args, kwargs
        self.retries, self.retry_delay_s = retries, float(retry_delay_s)
        self._next: ISmaccClientBehavior | None = behavior_type(*args, **kwargs)  # bad arguments fail now
        self.attempts = 0
        self.current: ISmaccClientBehavior | None = None
        self._outcome: SmaccEvent | None = None  # the running attempt's outcome, set from any thread
        self._failed_at_s: float | None = None
        self._lock = threading.Lock()
        self._closed = False

    def on_entry(self) -> None:
        self._start_attempt()

    def update(self) -> None:
        """Poll the running attempt; start the next one when the last failed and the delay is over."""
        attempt = self.current
        if isinstance(attempt, ISmaccUpdatable) and attempt._update_due(self.sm.now()):
            try:
                attempt.update()
            except Exception:
                _log.exception("CbRetry: %s.update raised; skipped", self.behavior_type.__name__)
        with self._lock:
            failure, self._outcome = self._outcome, None
        if failure is not None:
            self._exit_attempt()
            if self.attempts > self.retries:
                self._closed = True
                name = self.behavior_type.__name__
                self.post_failure_event(attempts=self.attempts, behavior=name,
                                        reason=getattr(failure, "reason", f"{name} failed"))
                return
            self._failed_at_s = self.sm.now()
        if (self.current is None and not self._closed and self._failed_at_s is not None
                and self.sm.now() - self._failed_at_s >= self.retry_delay_s):
            self._start_attempt()

    def on_exit(self) -> None:
        self._closed = True
        self._exit_attempt()

    def _start_attempt(self) -> None:
        attempt, self._next = self._next or self.behavior_type(*self.args, **self.kwargs), None
        self.attempts += 1
        self._failed_at_s = None
        attempt._attach(self.orthogonal, self.state)
        attempt.post_event = lambda event: self._on_attempt_event(attempt, event)  # type: ignore[method-assign]
        self.current = attempt
        _log.info("CbRetry: %s attempt %d of %d", self.behavior_type.__name__, self.attempts,
                  self.retries + 1)
        try:
            attempt._engine_entry()
        except Exception as exc:
            _log.exception("CbRetry: %s.on_entry raised", self.behavior_type.__name__)
            self._on_attempt_event(attempt, attempt.own_event(EvCbFailure)(reason=f"on_entry raised: {exc}"))

    def _on_attempt_event(self, attempt: ISmaccClientBehavior, event: SmaccEvent | type[SmaccEvent]) -> None:
        """An attempt's outcome ends it (success: CbRetry succeeds now); other events go to the machine."""
        if isinstance(event, type):
            event = event()
        if not isinstance(event, (EvCbSuccess, EvCbFailure, EvCbFinished)):
            self.post_event(event)
            return
        with self._lock:
            if attempt is not self.current or self._closed or self._outcome is not None:
                return  # a late or second outcome of an attempt already ended
            if isinstance(event, EvCbFailure):
                self._outcome = event
                return
            self._closed = True
        self.post_success_event(**{**vars(event), "attempts": self.attempts,
                                   "behavior": self.behavior_type.__name__})

    def _exit_attempt(self) -> None:
        attempt, self.current = self.current, None
        if attempt is not None:
            try:
                attempt._engine_exit(ATTEMPT_JOIN_S)
            except Exception:
                _log.exception("CbRetry: %s.on_exit raised; skipped", self.behavior_type.__name__)
