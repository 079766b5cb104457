"""Event generators: state-lifetime objects that post events from their own logic.

Declared in ``static_configure`` with ``static_create_event_generator(EgX, *args)``. The library
generator ``EgConditionalGenerator`` evaluates a predicate once on entry (``ONE_SHOT``) or on every
``update()`` poll (``ON_UPDATE``) and posts ``EvTrue[EgConditionalGenerator, State]`` or ``EvFalse[...]``.
Generators sit below the state that declares them and reach it through ``StatePort``.
"""

from __future__ import annotations

import enum
from collections.abc import Callable

from smacc_py.core.events import EvFalse, EvTrue, SmaccEvent
from smacc_py.core.ports import MachinePort, StatePort
from smacc_py.core.updatable import ISmaccUpdatable


class SmaccEventGenerator:
    """Base of every event generator (``smacc2::SmaccEventGenerator``)."""

    state: StatePort
    sm: MachinePort
    _seq: int

    def _attach(self, state: StatePort) -> None:
        self.state = state
        self.sm = state.sm
        self._seq = state.seq

    def on_entry(self) -> None:
        """Called after the owning state's ``on_entry``."""

    def on_exit(self) -> None:
        """Called when the owning state exits."""

    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post with CURRENT_STATE lifetime."""
        self.sm.post_event(event, owner_seq=self._seq)


class ConditionalGeneratorMode(enum.Enum):
    """When EgConditionalGenerator evaluates its predicate.

    SMACC2: ``smacc2::event_generators::ConditionalGeneratorMode``.
    """

    ONE_SHOT = "one_shot"
    """Once, on state entry."""
    ON_UPDATE = "on_update"
    """On every ``update()`` poll of the machine."""


class EgConditionalGenerator(SmaccEventGenerator, ISmaccUpdatable):
    """Posts ``EvTrue``/``EvFalse`` parameterised by (this generator type, owning state type)
    (``smacc2::event_generators::EgConditionalGenerator``)."""

    def __init__(self, mode: ConditionalGeneratorMode, predicate: Callable[[], bool]) -> None:
        if not isinstance(mode, ConditionalGeneratorMode):
            raise TypeError(f"EgConditionalGenerator: mode must be a ConditionalGeneratorMode, got {mode!r}")
        if not callable(predicate):
            raise TypeError(f"EgConditionalGenerator: predicate is not callable: {predicate!r}")
        self.mode = mode
        self.predicate = predicate

    def on_entry(self) -> None:
        if self.mode is ConditionalGeneratorMode.ONE_SHOT:
            self.check_predicate()

    def update(self) -> None:
        if self.mode is ConditionalGeneratorMode.ON_UPDATE:
            self.check_predicate()

    def check_predicate(self) -> None:
        """Evaluate the predicate now and post EvTrue or EvFalse."""
        template = EvTrue if self.predicate() else EvFalse
        self.post_event(template[type(self), type(self.state)])
