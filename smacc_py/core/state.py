"""``SmaccState``: states declared as classes, like SMACC2's ``SmaccState<St, Context, InnerInitial>``.

What a state class declares (all checked when the class is created, errors name the class):

* ``parent``: class keyword naming the context, i.e. the machine or a superstate
  (``class StiForward(SmaccState, parent=SsPatrol)``), or its name (``parent="SsPatrol"``), resolved when
  the machine is compiled: a machine split across modules then needs no import cycle, and superstates and
  their inner states may be defined in any order. A name matches a class of the same package (or of the
  same directory, or of the same function body); ``declared_names`` keeps these declarations until
  then. Omitted: a free top-level state that any machine reaching it adopts.
* ``reactions``: a list of ``Transition``; innermost state first, first match in list order wins.
* ``inner_initial_state``: makes the class a superstate (a class or a forward-referenced name).
* ``static_configure()`` classmethod: calls ``configure_orthogonal``, ``static_create_state_reactor`` and
  ``static_create_event_generator``; it runs once at class creation, so the whole graph is known
  before any state is entered (introspection, graph export, validation).

Instance hooks, in the order the engine calls them: ``runtime_configure``, ``on_entry``, then on the way
out ``on_exit_<TAG>`` (only on the state whose reaction fired, only for that exact tag) and ``on_exit``.

The declarations name orthogonal, behavior, reactor and generator classes, so those modules sit below
this one; the machine sits above (it is compiled from states) and a state reaches it through
``MachinePort``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

from smacc_py.core.client_behavior import ISmaccClientBehavior
from smacc_py.core.declared_names import register_state
from smacc_py.core.errors import InvalidDefinitionError, SmaccLookupError
from smacc_py.core.event_generators import SmaccEventGenerator
from smacc_py.core.events import (
    EvLoopContinue,
    EvLoopEnd,
    EvSequenceFinished,
    EvStateRequestFinish,
    SmaccEvent,
)
from smacc_py.core.global_data import MISSING
from smacc_py.core.orthogonal import Orthogonal
from smacc_py.core.ports import MachinePort, SmaccLogger
from smacc_py.core.reactors import StateReactor
from smacc_py.core.tags import TransitionTag
from smacc_py.core.transition import Transition

C = TypeVar("C")
S = TypeVar("S", bound="SmaccState")


@dataclass(frozen=True)
class BehaviorConfig:
    """``configure_orthogonal(Or, Cb, *args, **kwargs)``: Cb is built with these arguments on entry."""

    orthogonal: type[Orthogonal]
    behavior: type[ISmaccClientBehavior]
    args: tuple[Any, ...]
    kwargs: Mapping[str, Any]


@dataclass(frozen=True)
class ReactorConfig:
    """``static_create_state_reactor(Sr, OutputEvent, [InputEvents], *args, **kwargs)``."""

    reactor: type[StateReactor]
    output_event: type[SmaccEvent]
    input_events: tuple[type[SmaccEvent], ...]
    args: tuple[Any, ...]
    kwargs: Mapping[str, Any]


@dataclass(frozen=True)
class GeneratorConfig:
    """``static_create_event_generator(Eg, *args, **kwargs)``."""

    generator: type[SmaccEventGenerator]
    args: tuple[Any, ...]
    kwargs: Mapping[str, Any]


def _label(obj: object) -> str:
    return obj.__name__ if isinstance(obj, type) else repr(obj)


def _check_signature(owner: str, factory: Callable[..., Any], args: tuple[Any, ...],
                     kwargs: Mapping[str, Any]) -> None:
    try:
        signature = inspect.signature(factory)
    except (TypeError, ValueError):  # builtins without a signature: checked when built
        return
    try:
        signature.bind(*args, **kwargs)
    except TypeError as exc:
        raise InvalidDefinitionError(f"{owner}: bad arguments for {factory.__name__}{signature}: "
                                     f"{exc}") from None


class SmaccState:
    """Base class of every state and superstate (``smacc2::SmaccState<St, Context, InnerInitial>``);
    implements the ``StatePort`` its behaviors, reactors and generators use."""

    reactions: ClassVar[Sequence[Transition]] = ()
    inner_initial_state: ClassVar[type[SmaccState] | str | None] = None

    parent_decl: ClassVar[type | str | None] = None
    behavior_configs: ClassVar[tuple[BehaviorConfig, ...]] = ()
    reactor_configs: ClassVar[tuple[ReactorConfig, ...]] = ()
    generator_configs: ClassVar[tuple[GeneratorConfig, ...]] = ()
    _collecting: ClassVar[list[Any] | None] = None
    _exit_hooks: ClassVar[dict[type[TransitionTag], Callable[[SmaccState], None] | None]]

    def __init_subclass__(cls, parent: type | str | None = None, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if isinstance(parent, str):
            if not parent.isidentifier():
                raise InvalidDefinitionError(f"{cls.__name__}: parent={parent!r} is not a class name")
        elif parent is not None and not (
            isinstance(parent, type)
            and (issubclass(parent, SmaccState) or getattr(parent, "_is_smacc_state_machine", False))
        ):
            raise InvalidDefinitionError(
                f"{cls.__name__}: parent must be a SmaccState or SmaccStateMachineBase subclass or its "
                f"name, got {parent!r}"
            )
        cls.parent_decl = parent
        register_state(cls, parent)
        cls._exit_hooks = {}
        reactions = cls.__dict__.get("reactions", cls.reactions)
        if isinstance(reactions, (str, bytes)) or not isinstance(reactions, Iterable):
            raise InvalidDefinitionError(f"{cls.__name__}.reactions must be a list of Transition, got "
                                         f"{reactions!r}")
        cls.reactions = tuple(reactions)
        for index, item in enumerate(cls.reactions):
            if not isinstance(item, Transition):
                raise InvalidDefinitionError(f"{cls.__name__}.reactions[{index}] is not a Transition: "
                                             f"{item!r}")
        initial = cls.inner_initial_state
        if initial is not None and not isinstance(initial, str) and not (
            isinstance(initial, type) and issubclass(initial, SmaccState)
        ):
            raise InvalidDefinitionError(
                f"{cls.__name__}.inner_initial_state must be a SmaccState class or its name, got {initial!r}"
            )
        collected: list[Any] = []
        cls._collecting = collected
        try:
            cls.static_configure()
        finally:
            cls._collecting = None
        cls.behavior_configs = tuple(c for c in collected if isinstance(c, BehaviorConfig))
        cls.reactor_configs = tuple(c for c in collected if isinstance(c, ReactorConfig))
        cls.generator_configs = tuple(c for c in collected if isinstance(c, GeneratorConfig))

    # ------------------------------------------------------------------ static declarations
    @classmethod
    def static_configure(cls) -> None:
        """Declare behaviors, reactors and generators; runs once when the class is created."""

    @classmethod
    def _collect(cls, item: Any, what: str) -> None:
        if cls.__dict__.get("_collecting") is None:
            raise InvalidDefinitionError(f"{cls.__name__}: {what} may only be called from static_configure()")
        assert cls._collecting is not None
        cls._collecting.append(item)

    @classmethod
    def configure_orthogonal(cls, orthogonal: type[Orthogonal], behavior: type[ISmaccClientBehavior],
                             *args: Any, **kwargs: Any) -> None:
        """Run a new ``behavior(*args, **kwargs)`` on ``orthogonal`` every time this state is entered."""
        if not (isinstance(orthogonal, type) and issubclass(orthogonal, Orthogonal)):
            raise InvalidDefinitionError(
                f"{cls.__name__}.configure_orthogonal: {_label(orthogonal)} is not an Orthogonal"
            )
        if not (isinstance(behavior, type) and issubclass(behavior, ISmaccClientBehavior)):
            raise InvalidDefinitionError(
                f"{cls.__name__}.configure_orthogonal({orthogonal.__name__}, ...): {_label(behavior)} "
                "is not a client behavior class"
            )
        _check_signature(cls.__name__, behavior, args, kwargs)
        cls._collect(BehaviorConfig(orthogonal, behavior, args, dict(kwargs)), "configure_orthogonal")

    @classmethod
    def static_create_state_reactor(cls, reactor: type[StateReactor], output_event: type[SmaccEvent],
                                    input_events: Iterable[type[SmaccEvent]], *args: Any,
                                    **kwargs: Any) -> None:
        """Create ``reactor(*args, **kwargs)`` on entry; it posts ``output_event`` when it triggers."""
        if not (isinstance(reactor, type) and issubclass(reactor, StateReactor)):
            raise InvalidDefinitionError(
                f"{cls.__name__}.static_create_state_reactor: {_label(reactor)} is not a StateReactor"
            )
        inputs = tuple(input_events)
        for ev in (output_event, *inputs):
            if not (isinstance(ev, type) and issubclass(ev, SmaccEvent)):
                raise InvalidDefinitionError(
                    f"{cls.__name__}: reactor {reactor.__name__}: {_label(ev)} is not an event class"
                )
        if not inputs:
            raise InvalidDefinitionError(f"{cls.__name__}: reactor {reactor.__name__} needs at least one "
                                         f"input event")
        _check_signature(cls.__name__, reactor, args, kwargs)
        config = ReactorConfig(reactor, output_event, inputs, args, dict(kwargs))
        cls._collect(config, "static_create_state_reactor")

    @classmethod
    def static_create_event_generator(cls, generator: type[SmaccEventGenerator], *args: Any,
                                      **kwargs: Any) -> None:
        """Create ``generator(*args, **kwargs)`` on every entry of this state."""
        if not (isinstance(generator, type) and issubclass(generator, SmaccEventGenerator)):
            raise InvalidDefinitionError(
                f"{cls.__name__}.static_create_event_generator: {_label(generator)} is not a "
                "SmaccEventGenerator"
            )
        _check_signature(cls.__name__, generator, args, kwargs)
        cls._collect(GeneratorConfig(generator, args, dict(kwargs)), "static_create_event_generator")

    @classmethod
    def exit_hook(cls, tag: type[TransitionTag]) -> Callable[[SmaccState], None] | None:
        """The ``on_exit_<TAG>`` method for exactly this tag, or None (cached per class)."""
        hooks = cls._exit_hooks
        if tag not in hooks:
            hooks[tag] = getattr(cls, f"on_exit_{tag.__name__}", None)
        return hooks[tag]

    # ------------------------------------------------------------------ instance
    def __init__(self, sm: MachinePort, parent: SmaccState | None, seq: int) -> None:
        self.sm = sm
        self.parent = parent
        self.seq = seq
        self.behaviors: list[tuple[Orthogonal, ISmaccClientBehavior]] = []
        self.reactors: list[StateReactor] = []
        self.generators: list[SmaccEventGenerator] = []

    def runtime_configure(self) -> None:
        """Called after behaviors, reactors and generators are built, before any ``on_entry``."""

    def on_entry(self) -> None:
        """Called when the state is entered, before its behaviors' ``on_entry``."""

    def on_exit(self) -> None:
        """Called when the state is left, after its behaviors' ``on_exit``."""

    def __repr__(self) -> str:
        return f"<{type(self).__name__} #{self.seq}>"

    def get_logger(self) -> SmaccLogger:
        """The machine's logger (under the ROS runtime the node's logger, as SMACC2's ``getLogger()``)."""
        return self.sm.get_logger()

    getLogger = get_logger  # SMACC2's spelling

    # ------------------------------------------------------------------ helpers
    def post_event(self, event: SmaccEvent | type[SmaccEvent]) -> None:
        """Post an event with ABSOLUTE lifetime."""
        self.sm.post_event(event)

    def context(self, state_type: type[S]) -> S:
        """The active ancestor (or self) of type ``state_type``, e.g. a superstate holding a counter."""
        node: SmaccState | None = self
        while node is not None:
            if isinstance(node, state_type):
                return node
            node = node.parent
        raise SmaccLookupError(f"{type(self).__name__}: no active context of type {state_type.__name__}")

    def get_orthogonal(self, orthogonal_type: type[C]) -> C:
        """The machine's orthogonal of that type."""
        return self.sm.get_orthogonal(orthogonal_type)

    def requires_client(self, client_type: type[C]) -> C:
        """A client of any orthogonal; SmaccLookupError naming this state when absent."""
        return self.sm.requires_client(client_type, who=type(self).__name__)

    def requires_component(self, component_type: type[C]) -> C:
        """A component of any client; SmaccLookupError naming this state when absent."""
        return self.sm.requires_component(component_type, who=type(self).__name__)

    def get_client_behavior(self, orthogonal_type: type[Orthogonal], behavior_type: type[C],
                            index: int = 0) -> C:
        """The ``index``-th behavior of ``behavior_type`` this state runs on ``orthogonal_type``."""
        found = [b for o, b in self.behaviors
                 if isinstance(o, orthogonal_type) and isinstance(b, behavior_type)]
        if index >= len(found):
            raise SmaccLookupError(
                f"{type(self).__name__}: no behavior #{index} of type {behavior_type.__name__} on "
                f"{orthogonal_type.__name__}"
            )
        return found[index]

    def get_state_reactor(self, reactor_type: type[C]) -> C:
        """The first reactor of this state that is a ``reactor_type``."""
        for reactor in self.reactors:
            if isinstance(reactor, reactor_type):
                return reactor
        raise SmaccLookupError(f"{type(self).__name__}: no state reactor of type {reactor_type.__name__}")

    def get_event_generator(self, generator_type: type[C]) -> C:
        """The first event generator of this state that is a ``generator_type``."""
        for generator in self.generators:
            if isinstance(generator, generator_type):
                return generator
        raise SmaccLookupError(f"{type(self).__name__}: no event generator of type {generator_type.__name__}")

    def set_global_sm_data(self, name: str, value: Any) -> None:
        """Store a named value on the machine's blackboard."""
        self.sm.set_global_sm_data(name, value)

    def get_global_sm_data(self, name: str, default: Any = MISSING) -> Any:
        """Read a named value; ``default`` when given and absent, else SmaccLookupError."""
        return self.sm.get_global_sm_data(name, default)

    def check_while_loop_condition_and_throw_event(self, condition: Callable[[], bool]) -> bool:
        """Post ``EvLoopContinue[ThisState]`` when ``condition()`` holds, else ``EvLoopEnd[ThisState]``."""
        holds = bool(condition())
        self.post_event((EvLoopContinue if holds else EvLoopEnd)[type(self)])
        return holds

    def throw_sequence_finished_event(self) -> None:
        """Post ``EvSequenceFinished[ThisState]``."""
        self.post_event(EvSequenceFinished[type(self)])

    def request_finish(self) -> None:
        """Post ``EvStateRequestFinish[ThisState]``."""
        self.post_event(EvStateRequestFinish[type(self)])
