"""State reactors: state-lifetime objects that turn patterns of events into one output event.

Declared in ``static_configure`` with ``static_create_state_reactor(SrX, OutputEvent, [InputEvents],
*args)``. Every posted event is shown to the reactors of all active states *before* it is queued
(SMACC2 semantics), so a reactor's output is queued just *ahead* of the event that triggered it. Input
matching is by subclass, so a template (``EvCbSuccess``) listens to all of its parameterisations.
Reactors sit below the state that declares them and reach it through ``StatePort``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core.events import SmaccEvent
from smacc_py.core.ports import MachinePort, StatePort


class StateReactor:
    """Base of every reactor (``smacc2::StateReactor``): override ``on_event_notified`` and ``triggers``."""

    output_event: type[SmaccEvent]
    input_events: tuple[type[SmaccEvent], ...]
    state: StatePort
    sm: MachinePort
    _seq: int

    def _attach(self, state: StatePort, output_event: type[SmaccEvent],
                input_events: tuple[type[SmaccEvent], ...]) -> None:
        self.state = state
        self.sm = state.sm
        self._seq = state.seq
        self.output_event = output_event
        self.input_events = input_events

    def on_entry(self) -> None:
        """Called after the owning state's ``on_entry``."""

    def on_exit(self) -> None:
        """Called when the owning state exits."""

    def on_event_notified(self, event: SmaccEvent) -> None:
        """Called for each posted event that matches one of ``input_events``."""

    def triggers(self) -> bool:
        """Asked after each notified event; True posts ``output_event``."""
        return False

    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post with CURRENT_STATE lifetime (dropped once the owning state has begun to exit)."""
        self.sm.post_event(event, owner_seq=self._seq)

    def _notify(self, event: SmaccEvent) -> None:
        self.on_event_notified(event)
        if self.triggers():
            self.post_event(self.output_event)


class SrAllEventsGo(StateReactor):
    """Posts its output (``EvAllGo``) once every input event type has been seen; then starts over
    (``smacc2::state_reactors::SrAllEventsGo``)."""

    def __init__(self) -> None:
        self._seen: set[type[SmaccEvent]] = set()

    def on_event_notified(self, event: SmaccEvent) -> None:
        for wanted in self.input_events:
            if isinstance(event, wanted):
                self._seen.add(wanted)

    def triggers(self) -> bool:
        if len(self._seen) < len(set(self.input_events)):
            return False
        self._seen.clear()
        return True

    def pending(self) -> list[type[SmaccEvent]]:
        """Input event types not seen yet (for logging and tests)."""
        return [ev for ev in self.input_events if ev not in self._seen]


class SrConditional(StateReactor):
    """Posts its output (``EvConditionalTrue``) whenever ``predicate(event)`` holds for an input event
    (``smacc2::state_reactors::SrConditional``)."""

    def __init__(self, predicate: Callable[[Any], bool]) -> None:
        if not callable(predicate):
            raise TypeError(f"SrConditional needs a callable predicate, got {predicate!r}")
        self._predicate = predicate
        self._fire = False

    def on_event_notified(self, event: SmaccEvent) -> None:
        self._fire = bool(self._predicate(event))

    def triggers(self) -> bool:
        fire, self._fire = self._fire, False
        return fire


class SrEventCountdown(StateReactor):
    """Posts its output (``EvCountdownEnd``) once, when ``count`` input events have been seen
    (``smacc2::state_reactors::SrEventCountdown``)."""

    def __init__(self, count: int) -> None:
        if count < 1:
            raise ValueError(f"SrEventCountdown: count must be >= 1, got {count}")
        self.remaining = count

    def on_event_notified(self, event: SmaccEvent) -> None:
        self.remaining -= 1

    def triggers(self) -> bool:
        return self.remaining == 0
