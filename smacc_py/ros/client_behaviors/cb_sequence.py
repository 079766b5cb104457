"""``CbSequence``: run behaviors one after another inside one state (SMACC2's CbSequence).

Each step is a behavior class (or any callable returning a behavior) with its arguments, built
fresh on every entry of the state: ``CbSequence().then(CbSleepFor, 1.0).then(CbCallService, Trigger,
"/arm")``, or ``CbSequence([functools.partial(CbSleepFor, 1.0), ...])``. A step is done when it posts
EvCbSuccess, or, for an async behavior, when its ``on_entry`` returns (EvCbFinished); then its
``on_exit`` runs and the next step starts. When the last step is done the sequence posts
``EvSequenceFinished[State]`` and ``EvCbSuccess[CbSequence, Or](steps=n)``. A step posting EvCbFailure
(or failing to build) stops the sequence with ``EvCbFailure[CbSequence, Or](step=i, behavior=name,
reason=...)``. The steps' own success, failure and finished events stay inside the sequence; any
other event a step posts reaches the machine.

Steps run on the machine thread: a step finished from that thread (in its ``on_entry``, a ROS
callback, a poll) starts the next one at once; one finished from an async step's own thread starts
it at the next runtime poll (1 / signal_detector_loop_freq s). The current step gets its
ISmaccUpdatable polls through the sequence. On state exit the running step is exited.
"""

from __future__ import annotations

import functools
import logging
import threading
from collections.abc import Callable, Sequence
from typing import Any

from smacc_py.core import (
    EvCbFailure,
    EvCbFinished,
    EvCbSuccess,
    EvSequenceFinished,
    ISmaccClientBehavior,
    ISmaccUpdatable,
    SmaccClientBehavior,
    SmaccEvent,
)

_log = logging.getLogger("smacc_py")

StepFactory = Callable[[], ISmaccClientBehavior]
DEFAULT_STEP_JOIN_S = 5.0  # s, SmaccEngineParams.async_join_timeout_s's default


class CbSequence(SmaccClientBehavior, ISmaccUpdatable):
    """Runs ``steps`` (behavior factories) in order; more with ``then``.

    Attributes:
        step_join_timeout_s: bound (s) on waiting for an async step's ``on_entry`` when it is exited
            (the step's own ``join_timeout_s`` wins), as the engine's ``async_join_timeout_s``.
        index: the step running (0-based), -1 before the first, ``len(steps)`` after the last.
        current: the step running, None between steps and after the end.
    """

    step_join_timeout_s: float = DEFAULT_STEP_JOIN_S

    def __init__(self, steps: Sequence[StepFactory] = ()) -> None:
        self.steps: list[StepFactory] = []
        for step in steps:
            self.then(step)
        self.index = -1
        self.current: ISmaccClientBehavior | None = None

    def then(self, behavior: Callable[..., ISmaccClientBehavior], *args: Any, **kwargs: Any) -> CbSequence:
        """Append a step built as ``behavior(*args, **kwargs)`` on each entry; returns self to chain."""
        if not callable(behavior):
            raise TypeError(f"CbSequence step {len(self.steps)}: {behavior!r} is not a behavior class or "
                            "factory")
        self.steps.append(functools.partial(behavior, *args, **kwargs) if args or kwargs else behavior)
        return self

    def on_entry(self) -> None:
        self._lock = threading.Lock()
        self._machine_thread = threading.get_ident()
        self._stepping = False
        self._closed = False
        self._step_outcome: tuple[bool, SmaccEvent] | None = None
        self._advance()

    def update(self) -> None:
        """Poll the running step, then start the next one if an async step has finished meanwhile."""
        step = self.current
        if isinstance(step, ISmaccUpdatable) and step._update_due(self.sm.now()):
            try:
                step.update()
            except Exception:
                _log.exception("CbSequence: %s.update raised; skipped", type(step).__name__)
        self._advance()

    def on_exit(self) -> None:
        self._closed = True
        self._exit_current()

    # ------------------------------------------------------------------ stepping
    def _advance(self) -> None:
        """Finish steps that are done and start the next ones, until one is running or the end."""
        if self._stepping or self._closed:
            return
        self._stepping = True
        try:
            while not self._closed:
                if self.current is not None:
                    with self._lock:
                        outcome, self._step_outcome = self._step_outcome, None
                    if outcome is None:
                        return
                    name = type(self.current).__name__
                    self._exit_current()
                    ok, event = outcome
                    if not ok:
                        self._fail(name, getattr(event, "reason", f"{name} failed"))
                        return
                if not self._start_next():
                    return
        finally:
            self._stepping = False

    def _start_next(self) -> bool:
        """Start step ``index + 1``; False at the end of the sequence or when the step cannot start."""
        self.index += 1
        if self.index >= len(self.steps):
            self._closed = True
            self.post_event(EvSequenceFinished[type(self.state)])
            self.post_success_event(steps=len(self.steps))
            return False
        factory = self.steps[self.index]
        try:
            step = factory()
            if not isinstance(step, ISmaccClientBehavior):
                raise TypeError(f"it built {step!r}, which is not a client behavior")
        except Exception as exc:
            _log.exception("CbSequence: building step %d failed", self.index)
            self._fail(getattr(factory, "__name__", repr(factory)), f"building the step failed: {exc}")
            return False
        step._attach(self.orthogonal, self.state)
        setattr(step, "post_event", functools.partial(self._on_step_event, step))  # noqa: B010
        self.current = step
        try:
            step._engine_entry()
        except Exception as exc:
            _log.exception("CbSequence: %s.on_entry raised", type(step).__name__)
            self._on_step_event(step, step.own_event(EvCbFailure)(reason=f"on_entry raised: {exc}"))
        return True

    def _on_step_event(self, step: ISmaccClientBehavior, event: SmaccEvent | type[SmaccEvent]) -> None:
        """What a step posts: its outcome is kept for ``_advance``, anything else goes to the machine."""
        if isinstance(event, type):
            event = event()
        if isinstance(event, (EvCbSuccess, EvCbFinished, EvCbFailure)):
            if step is self.current:
                with self._lock:
                    if self._step_outcome is None:
                        self._step_outcome = (not isinstance(event, EvCbFailure), event)
                if threading.get_ident() == self._machine_thread:
                    self._advance()
            return
        self.post_event(event)

    def _exit_current(self) -> None:
        step, self.current = self.current, None
        if step is not None:
            try:
                step._engine_exit(self.step_join_timeout_s)
            except Exception:
                _log.exception("CbSequence: %s.on_exit raised; skipped", type(step).__name__)

    def _fail(self, name: str, reason: str) -> None:
        self._closed = True
        self.post_failure_event(step=self.index, behavior=name, reason=f"CbSequence step {self.index} "
                                f"({name}): {reason}")
