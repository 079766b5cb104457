"""Observers, transition records and the machine's observer registry: what the ROS runtime needs for
introspection.

The engine calls observers synchronously: ``on_event_posted`` on the posting thread (an async
behavior's thread, say), everything else on the machine thread (the ROS runtime's executor), in
order. Observers must be quick (queue the work and publish elsewhere) and must not post events from
``on_transition`` or the exit/entry callbacks. Exceptions they raise are logged and ignored.
``TransitionRecord`` carries the fields of ``smacc2_msgs/SmaccTransitionLogEntry``; treat it as
read-only (it is not frozen only because a frozen dataclass is slow to build, and one is built per
transition on the hot path).

This is the engine's outgoing interface, so it sits below ``state_machine``, which calls it. The ``sm``
argument of every callback is the reporting ``SmaccStateMachineBase``; it is typed ``Any`` here because
this module cannot name that class, and ``Any`` (unlike ``MachinePort``) lets subclasses annotate the
argument as ``SmaccStateMachineBase`` without breaking the override rules.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from smacc_py.core.events import SmaccEvent
from smacc_py.core.state import SmaccState
from smacc_py.core.tags import TransitionTag

_log = logging.getLogger("smacc_py")


@dataclass(slots=True)
class TransitionRecord:
    """One taken transition (``smacc2_msgs/SmaccTransitionLogEntry``); ``stamp_s`` is the machine clock (s).

    ``target`` is the declared destination (the superstate for ``History``), as in ``SmaccTransition``;
    ``leaf`` is the innermost state the transition ended in (after inner initial states or history).
    """

    index: int
    source: type[SmaccState]
    target: type[SmaccState]
    leaf: type[SmaccState]
    tag: type[TransitionTag]
    event: SmaccEvent
    history: bool
    stamp_s: float

    def key(self) -> tuple[str, str, str]:
        """(source name, target name, tag name): handy for asserting transition sequences."""
        return (self.source.__name__, self.target.__name__, self.tag.__name__)


class SmaccObserver:
    """Base with no-op callbacks; override the ones you need and ``sm.add_observer(obs)``.

    SMACC2 has no equivalent class: its ``ISmaccStateMachine`` publishes these moments itself
    (``smacc2_msgs/SmaccStatus``, ``SmaccTransitionLogEntry``); here the ROS runtime is one observer.
    """

    def on_event_posted(self, sm: Any, event: SmaccEvent) -> None:
        """An event was queued (after the state reactors saw it)."""

    def on_event_dropped(self, sm: Any, event: SmaccEvent) -> None:
        """A CURRENT_STATE event was dropped because the state that posted it has exited."""

    def on_event_unhandled(self, sm: Any, event: SmaccEvent) -> None:
        """No active state had a matching transition whose guard accepted the event."""

    def on_transition(self, sm: Any, record: TransitionRecord) -> None:
        """A transition was taken; called after ``on_exit_<TAG>`` and before any state exits."""

    def on_state_exited(self, sm: Any, state: SmaccState) -> None:
        """A state finished exiting (after its ``on_exit``)."""

    def on_state_entered(self, sm: Any, state: SmaccState) -> None:
        """A state finished entering (after its behaviors', reactors' and generators' ``on_entry``)."""


class ObserverRegistry:
    """The machine's observers and the call into them; ``SmaccStateMachineBase`` inherits it.

    The tuple is replaced, never mutated, so a dispatch that is iterating it is not disturbed by an
    observer added or removed meanwhile (from another thread or from a callback).
    """

    # Set by SmaccStateMachineBase.__init__.
    _observers: tuple[SmaccObserver, ...]

    def add_observer(self, observer: SmaccObserver) -> None:
        """Register an observer (see ``SmaccObserver`` for the threading contract)."""
        self._observers = (*self._observers, observer)

    def remove_observer(self, observer: SmaccObserver) -> None:
        """Unregister an observer."""
        self._observers = tuple(o for o in self._observers if o is not observer)

    def _state_entered(self, state: SmaccState) -> None:
        """Observers' ``on_state_entered`` (the state lifecycle calls it; it cannot import this module)."""
        self._notify(SmaccObserver.on_state_entered, state)

    def _state_exited(self, state: SmaccState) -> None:
        """Observers' ``on_state_exited``."""
        self._notify(SmaccObserver.on_state_exited, state)

    def _notify(self, hook: Callable[..., None], arg: Any) -> None:
        """Call ``hook`` (a ``SmaccObserver`` method: a misspelt one fails at import, not silently)
        as overridden by each observer, with ``(sm, arg)``."""
        method = hook.__name__
        for observer in self._observers:
            try:
                getattr(observer, method)(self, arg)
            except Exception:
                _log.exception("observer %s.%s raised; ignored", type(observer).__name__, method)
