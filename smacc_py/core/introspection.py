"""Static description of a machine from its declarations, mirroring the smacc2_msgs messages.

``describe_state_machine`` needs no running machine: states, levels, children, transitions with tags,
orthogonals with their behaviors, reactors and generators all come from the class declarations (the
compiled ``MachineModel``). Client names are known only after ``initialize()``, so they are passed in by
``SmaccStateMachineBase.describe()``. The ROS runtime maps these frozen dataclasses one-to-one onto
``SmaccStateMachine``/``SmaccState``/``SmaccTransition``/``SmaccOrthogonal``/... messages.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from smacc_py.core.events import SmaccEvent
from smacc_py.core.model import MachineModel, TransitionPlan, compile_model


def _name(obj: object) -> str:
    return obj.__name__ if isinstance(obj, type) else ("" if obj is None else str(obj))


@dataclass(frozen=True)
class EventDescription:
    """``smacc2_msgs/SmaccEvent``."""

    event_type: str
    event_object_tag: str
    event_source: str
    label: str

    @classmethod
    def of(cls, event: type[SmaccEvent]) -> EventDescription:
        """Describe an event class: template name, orthogonal (2nd parameter), source (1st parameter)."""
        return cls(event.template.__name__, _name(event.param(1)), _name(event.param(0)),
                   event.get_event_label())


@dataclass(frozen=True)
class TransitionDescription:
    """``smacc2_msgs/SmaccTransition``."""

    index: int
    transition_name: str
    transition_type: str
    destiny_state_name: str
    source_state_name: str
    history_node: bool
    event: EventDescription


@dataclass(frozen=True)
class OrthogonalDescription:
    """``smacc2_msgs/SmaccOrthogonal``."""

    name: str
    client_behavior_names: tuple[str, ...]
    client_names: tuple[str, ...]


@dataclass(frozen=True)
class StateReactorDescription:
    """``smacc2_msgs/SmaccStateReactor``."""

    index: int
    type_name: str
    object_tag: str
    event_sources: tuple[EventDescription, ...]


@dataclass(frozen=True)
class EventGeneratorDescription:
    """``smacc2_msgs/SmaccEventGenerator``."""

    index: int
    type_name: str
    object_tag: str


@dataclass(frozen=True)
class StateDescription:
    """``smacc2_msgs/SmaccState`` (plus ``inner_initial_state``, empty for leaves)."""

    index: int
    name: str
    children_states: tuple[str, ...]
    level: int
    transitions: tuple[TransitionDescription, ...]
    orthogonals: tuple[OrthogonalDescription, ...]
    state_reactors: tuple[StateReactorDescription, ...]
    event_generators: tuple[EventGeneratorDescription, ...]
    inner_initial_state: str = ""


@dataclass(frozen=True)
class StateMachineDescription:
    """``smacc2_msgs/SmaccStateMachine`` (plus the machine name and its initial state)."""

    name: str
    initial_state: str
    states: tuple[StateDescription, ...]

    def state(self, name: str) -> StateDescription:
        """The description of the state called ``name``; KeyError when there is none."""
        for state in self.states:
            if state.name == name:
                return state
        raise KeyError(f"{self.name} has no state {name!r}")


def _transition(plan: TransitionPlan, index: int) -> TransitionDescription:
    target = plan.target.__name__
    return TransitionDescription(
        index=index,
        transition_name=f"Transition<{plan.event.get_event_label()}, {target}, {plan.tag.__name__}>",
        transition_type=plan.tag.__name__,
        destiny_state_name=target,
        source_state_name=plan.source.__name__,
        history_node=plan.history,
        event=EventDescription.of(plan.event),
    )


def describe_model(model: MachineModel, name: str | None = None,
                   client_names: Mapping[str, Sequence[str]] | None = None) -> StateMachineDescription:
    """Describe a compiled model; ``client_names`` maps orthogonal name → its clients' names."""
    clients = client_names or {}
    states: list[StateDescription] = []
    transition_index = 0
    for info in model.states.values():
        cls = info.state
        transitions = []
        for plan in model.plans[cls]:
            transitions.append(_transition(plan, transition_index))
            transition_index += 1
        behaviors: dict[str, list[str]] = {}
        for cfg in cls.behavior_configs:
            behaviors.setdefault(cfg.orthogonal.__name__, []).append(cfg.behavior.__name__)
        orthogonals = tuple(
            OrthogonalDescription(or_name, tuple(names), tuple(clients.get(or_name, ())))
            for or_name, names in behaviors.items()
        )
        reactors = tuple(
            StateReactorDescription(i, r.reactor.__name__, cls.__name__,
                                    tuple(EventDescription.of(ev) for ev in r.input_events))
            for i, r in enumerate(model.reactors[cls])
        )
        generators = tuple(
            EventGeneratorDescription(i, g.generator.__name__, cls.__name__)
            for i, g in enumerate(cls.generator_configs)
        )
        states.append(StateDescription(
            index=info.index, name=cls.__name__, children_states=tuple(c.__name__ for c in info.children),
            level=info.level, transitions=tuple(transitions), orthogonals=orthogonals,
            state_reactors=reactors, event_generators=generators,
            inner_initial_state=_name(info.inner_initial),
        ))
    return StateMachineDescription(name or model.sm_type.__name__, model.initial.__name__, tuple(states))


def describe_state_machine(sm_type: type) -> StateMachineDescription:
    """Describe a machine class from its declarations alone (compiles and validates it)."""
    return describe_model(compile_model(sm_type))
