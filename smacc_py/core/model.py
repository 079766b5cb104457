"""Compiles a machine class's declarations into a validated, precomputed model.

Everything the engine needs at runtime that depends only on declarations is computed here once per
machine class: the state tree (parents, levels, children, inner initial states; a ``parent="Name"`` is
resolved here among the machine and its states, then bound for good); every transition's
resolved target and event (state names among event parameters, e.g. ``EvLoopEnd["StLoop"]``, are
forward references too, in transitions and in reactor declarations); the states a transition exits
(``keep_depth``: how many outer states stay active) and enters (``entry_path``); the tag-specific exit
hook; and per-(leaf state, event class) dispatch tables (innermost state first, declaration order),
built lazily and cached. The same model feeds introspection and graph export, so what is drawn is
what runs.

Definition errors found here (unknown target or parent names, history of a non-superstate, unreachable states,
superstates without an inner initial state, states claimed by another machine) raise
``InvalidDefinitionError`` naming the class at fault; the machine compiles on first instantiation,
``validate()`` or ``describe_state_machine()``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from smacc_py.core.declared_names import bind_parent, declared_children, home, named_parent_orphans
from smacc_py.core.errors import InvalidDefinitionError
from smacc_py.core.events import SmaccEvent
from smacc_py.core.state import ReactorConfig, SmaccState
from smacc_py.core.tags import TransitionTag
from smacc_py.core.transition import Guard, History, Transition


@dataclass(frozen=True, slots=True)
class TransitionPlan:
    """A transition with everything resolved that the engine needs to execute it."""

    source: type[SmaccState]
    source_level: int
    index: int
    transition: Transition
    event: type[SmaccEvent]
    target: type[SmaccState]
    tag: type[TransitionTag]
    guard: Guard | None
    history: bool
    keep_depth: int
    entry_path: tuple[type[SmaccState], ...]
    tag_hook: Callable[[SmaccState], None] | None


@dataclass(frozen=True, slots=True)
class StateInfo:
    """Position of a state in the tree; ``level`` 0 is top level (``SmaccState.level`` in smacc2_msgs)."""

    index: int
    state: type[SmaccState]
    parent: type[SmaccState] | None
    level: int
    children: tuple[type[SmaccState], ...]
    inner_initial: type[SmaccState] | None


class MachineModel:
    """The compiled, validated form of one machine class.

    SMACC2 builds the same state tree from the C++ types in ``smacc2::introspection::SmaccStateMachineInfo``;
    its transitions are dispatched by Boost.Statechart, for which ``TransitionPlan`` stands in here.
    """

    def __init__(self, sm_type: type) -> None:
        self.sm_type = sm_type
        self._names = self._declared_names()
        orphans = named_parent_orphans(home(sm_type))
        if orphans:
            raise InvalidDefinitionError("; ".join(
                f"{c.__name__} ({c.__module__}): parent={getattr(c, 'parent_decl', None)!r} names no state "
                f"of {sm_type.__name__} (nor any state or machine next to it; states of "
                f"{sm_type.__name__}: {', '.join(sorted(self._names)) or 'none'})" for c in orphans))
        initial_ref = getattr(sm_type, "initial_state", None)
        if initial_ref is None:
            raise InvalidDefinitionError(f"{sm_type.__name__}: no initial_state declared")
        self.initial = self._resolve(initial_ref, sm_type, f"{sm_type.__name__}.initial_state")
        self._parents: dict[type[SmaccState], type[SmaccState] | None] = {}
        self._inner: dict[type[SmaccState], type[SmaccState] | None] = {}
        self._targets: dict[tuple[type[SmaccState], int], tuple[type[SmaccState], bool]] = {}
        self._discover()
        self.chains = {cls: self._chain(cls) for cls in self._parents}
        self.superstates = frozenset(cls for cls, inner in self._inner.items() if inner is not None)
        children: dict[type[SmaccState], list[type[SmaccState]]] = {cls: [] for cls in self._parents}
        for cls, parent in self._parents.items():
            if parent is not None:
                children[parent].append(cls)
        self.states: dict[type[SmaccState], StateInfo] = {
            cls: StateInfo(i, cls, self._parents[cls], len(self.chains[cls]) - 1, tuple(children[cls]),
                           self._inner[cls])
            for i, cls in enumerate(self._parents)
        }
        self.plans: dict[type[SmaccState], tuple[TransitionPlan, ...]] = {
            cls: tuple(self._plan(cls, i, tr) for i, tr in enumerate(cls.reactions)) for cls in self._parents
        }
        self.reactors: dict[type[SmaccState], tuple[ReactorConfig, ...]] = {
            cls: tuple(self._resolve_reactor(cls, cfg) for cfg in cls.reactor_configs)
            for cls in self._parents
        }
        self.initial_path = self.chains[self.initial] + self._descent(self.initial)
        for cls, parent in self._parents.items():  # compiled: bind parent="Name" declarations for good
            if isinstance(cls.parent_decl, str):
                bind_parent(cls, parent if parent is not None else sm_type)
        self._tables: dict[type[SmaccState], dict[type[SmaccEvent], tuple[TransitionPlan, ...]]] = {}

    # ------------------------------------------------------------------ discovery and validation
    def _declared_names(self) -> dict[str, type[SmaccState]]:
        names: dict[str, type[SmaccState]] = {}
        pending: list[type] = [self.sm_type]
        while pending:
            for child in declared_children(pending.pop()):
                names.setdefault(child.__name__, child)
                pending.append(child)
        return names

    def _resolve(self, ref: Any, owner: type, where: str) -> type[SmaccState]:
        if isinstance(ref, str):
            found = self._names.get(ref)
            if found is None:
                module = sys.modules.get(owner.__module__)
                found = getattr(module, ref, None) if module is not None else None
            if found is None:
                known = ", ".join(sorted(self._names)) or "none declared with parent="
                raise InvalidDefinitionError(
                    f"{where}: unknown state {ref!r} (states of {self.sm_type.__name__}: {known})"
                )
            ref = found
        if not (isinstance(ref, type) and issubclass(ref, SmaccState)) or ref is SmaccState:
            raise InvalidDefinitionError(f"{where}: {ref!r} is not a SmaccState subclass")
        return ref

    def _parent_decl(self, cls: type[SmaccState]) -> type | None:
        """``cls.parent_decl`` with a name (``parent="MsRunMode"``) resolved to the machine or its state."""
        decl = cls.parent_decl
        if not isinstance(decl, str):
            return decl
        if decl == self.sm_type.__name__ and home(self.sm_type) == home(cls):
            return self.sm_type
        found = self._names.get(decl)
        if found is None:
            known = ", ".join(sorted(self._names)) or "none"
            raise InvalidDefinitionError(f"{cls.__name__}: parent={decl!r} names no state of "
                                         f"{self.sm_type.__name__} (its states: {known})")
        return found

    def _discover(self) -> None:
        pending = [self.initial]
        while pending:
            cls = pending.pop(0)
            if cls in self._parents:
                continue
            decl = self._parent_decl(cls)
            if decl is not None and not issubclass(decl, SmaccState) and decl is not self.sm_type:
                raise InvalidDefinitionError(
                    f"{cls.__name__} belongs to {decl.__name__} (parent=) but is reached from "
                    f"{self.sm_type.__name__}"
                )
            parent = decl if decl is not None and issubclass(decl, SmaccState) else None
            self._parents[cls] = parent
            if parent is not None:
                pending.append(parent)
            inner_ref = cls.inner_initial_state
            inner = (None if inner_ref is None
                     else self._resolve(inner_ref, cls, f"{cls.__name__}.inner_initial_state"))
            if inner is None and declared_children(cls):
                names = ", ".join(c.__name__ for c in declared_children(cls))
                raise InvalidDefinitionError(
                    f"{cls.__name__} has inner states ({names}) but declares no inner_initial_state"
                )
            if inner is not None and self._parent_decl(inner) is not cls:
                raise InvalidDefinitionError(
                    f"{cls.__name__}.inner_initial_state {inner.__name__} must declare parent={cls.__name__}"
                )
            self._inner[cls] = inner
            if inner is not None:
                pending.append(inner)
            for i, tr in enumerate(cls.reactions):
                where = f"{cls.__name__}.reactions[{i}] {tr!r}"
                history = isinstance(tr.target, History)
                ref = tr.target.state if isinstance(tr.target, History) else tr.target
                target = self._resolve(ref, cls, where)
                if history and target.inner_initial_state is None:
                    raise InvalidDefinitionError(
                        f"{where}: History() needs a superstate, {target.__name__} has no inner states"
                    )
                self._targets[(cls, i)] = (target, history)
                pending.append(target)
        unreachable = [cls.__name__ for cls in self._expected_states() if cls not in self._parents]
        if unreachable:
            raise InvalidDefinitionError(
                f"{self.sm_type.__name__}: state(s) {', '.join(unreachable)} are declared but unreachable "
                f"from the initial state {self.initial.__name__} (no transition or inner_initial_state "
                "leads there)"
            )

    def _expected_states(self) -> list[type[SmaccState]]:
        """The states the machine must reach from its initial state.

        Those declared with ``parent=`` the machine or a state it reaches, and the free top-level states
        (no ``parent=``) defined next to the machine or to one of its reached free states: same module and
        same scope (module level, or one function body). Free states are adopted by whichever machine
        reaches them, so a forgotten transition into one would otherwise go unnoticed. A class that other
        states subclass is a template, not a state (sm_battery_patrol's ``_GoTo``), and is skipped.
        """
        expected = dict.fromkeys(self._names.values())
        for cls in list(self._parents):
            expected.update(dict.fromkeys(declared_children(cls)))
        scopes = {_scope(self.sm_type)} | {_scope(cls) for cls in self._parents if cls.parent_decl is None}
        for cls in _state_classes():
            if cls.parent_decl is None and _scope(cls) in scopes and not cls.__subclasses__():
                expected.setdefault(cls)
        return list(expected)

    def _chain(self, cls: type[SmaccState]) -> tuple[type[SmaccState], ...]:
        chain: list[type[SmaccState]] = []
        node: type[SmaccState] | None = cls
        while node is not None:
            chain.append(node)
            node = self._parents[node]
        return tuple(reversed(chain))

    def _descent(self, cls: type[SmaccState]) -> tuple[type[SmaccState], ...]:
        path: list[type[SmaccState]] = []
        inner = self._inner[cls]
        while inner is not None:
            path.append(inner)
            inner = self._inner[inner]
        return tuple(path)

    def _resolve_event(self, event: type[SmaccEvent], owner: type[SmaccState],
                       where: str) -> type[SmaccEvent]:
        """Replace state names among an event's parameters (``EvLoopEnd["StLoop"]``) by the classes."""
        if not any(isinstance(p, str) for p in event.params):
            return event
        params = tuple(self._resolve(p, owner, where) if isinstance(p, str) else p for p in event.params)
        return event.template[params]

    def _resolve_reactor(self, owner: type[SmaccState], cfg: ReactorConfig) -> ReactorConfig:
        where = f"{owner.__name__}: reactor {cfg.reactor.__name__}"
        output = self._resolve_event(cfg.output_event, owner, where)
        inputs = tuple(self._resolve_event(ev, owner, where) for ev in cfg.input_events)
        if output is cfg.output_event and inputs == cfg.input_events:
            return cfg
        return replace(cfg, output_event=output, input_events=inputs)

    def _plan(self, source: type[SmaccState], index: int, tr: Transition) -> TransitionPlan:
        target, history = self._targets[(source, index)]
        event = self._resolve_event(tr.event, source, f"{source.__name__}.reactions[{index}] {tr!r}")
        src_chain, dst_chain = self.chains[source], self.chains[target]
        keep = 0
        limit = min(len(src_chain), len(dst_chain)) - 1  # the common context is a *proper* ancestor of both
        while keep < limit and src_chain[keep] is dst_chain[keep]:
            keep += 1
        return TransitionPlan(
            source=source, source_level=len(src_chain) - 1, index=index, transition=tr, event=event,
            target=target, tag=tr.tag, guard=tr.guard, history=history, keep_depth=keep,
            entry_path=dst_chain[keep:] + self._descent(target), tag_hook=source.exit_hook(tr.tag),
        )

    # ------------------------------------------------------------------ runtime queries
    def table_for(self, leaf: type[SmaccState]) -> dict[type[SmaccEvent], tuple[TransitionPlan, ...]]:
        """The dispatch cache of an active leaf: event class → candidate plans, innermost first."""
        table = self._tables.get(leaf)
        if table is None:
            table = self._tables[leaf] = {}
        return table

    def candidates(self, leaf: type[SmaccState], event_type: type[SmaccEvent]) -> tuple[TransitionPlan, ...]:
        """Plans whose event matches ``event_type``: leaf's reactions first, then its ancestors'."""
        return tuple(
            plan
            for cls in reversed(self.chains[leaf])
            for plan in self.plans[cls]
            if issubclass(event_type, plan.event)
        )

    def history_path(self, plan: TransitionPlan,
                     last_leaf: type[SmaccState] | None) -> tuple[type[SmaccState], ...]:
        """States to enter for a history transition: back down to ``last_leaf`` or the default path."""
        if last_leaf is None:
            return plan.entry_path
        return self.chains[last_leaf][plan.keep_depth:]

    def configured_orthogonals(self) -> dict[type, list[tuple[type[SmaccState], type]]]:
        """Orthogonal type → [(state, behavior type)] over every state of the machine."""
        used: dict[type, list[tuple[type[SmaccState], type]]] = {}
        for cls in self.states:
            for cfg in cls.behavior_configs:
                used.setdefault(cfg.orthogonal, []).append((cls, cfg.behavior))
        return used


def _scope(cls: type) -> tuple[str, str]:
    """(module, enclosing qualified name): where a class is defined, e.g. a test function's body."""
    return cls.__module__, cls.__qualname__.rpartition(".")[0]


def _state_classes() -> list[type[SmaccState]]:
    """Every SmaccState subclass alive in the process, breadth first."""
    found: list[type[SmaccState]] = []
    pending: list[type[SmaccState]] = [SmaccState]
    while pending:
        for sub in pending.pop(0).__subclasses__():
            found.append(sub)
            pending.append(sub)
    return found


def compile_model(sm_type: type) -> MachineModel:
    """The cached model of a machine class, compiling (and validating) it on first use."""
    model = sm_type.__dict__.get("_smacc_model")
    if not isinstance(model, MachineModel):
        model = MachineModel(sm_type)
        type.__setattr__(sm_type, "_smacc_model", model)
    return model
