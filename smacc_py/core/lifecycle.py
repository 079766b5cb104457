"""Entering and leaving one state, in SMACC2's exact order (reference/smacc2.md §1 "Lifecycle ordering").

Entry: push state → every orthogonal opens a behavior slot → build the static behaviors, reactors and
generators → state ``runtime_configure`` → behaviors' ``runtime_configure`` → state ``on_entry`` →
behaviors' ``on_entry`` (async ones start their thread), reactors' and generators' ``on_entry``.

Exit: behaviors' ``on_exit`` (async ones first get the shutdown request and a bounded join), reactors'
and generators' ``on_exit`` → state ``on_exit`` → orthogonal slots closed → pop. Exceptions raised by
user hooks are logged with their traceback and skipped, so one faulty hook never kills the machine.

These functions work on the machine's bookkeeping (its state stack, orthogonals, active reactors), which
``LifecycleHost`` names; ``SmaccStateMachineBase`` satisfies it. They are split from the machine so the
entry and exit order can be read in one place (SMACC2 spreads it over ``SmaccState``'s constructor and
``ISmaccStateMachine::notifyOnStateEntryStart``/``notifyOnStateExitting``).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any, Protocol

from smacc_py.core.model import MachineModel
from smacc_py.core.orthogonal import Orthogonal
from smacc_py.core.params import SmaccEngineParams
from smacc_py.core.ports import MachinePort
from smacc_py.core.reactors import StateReactor
from smacc_py.core.state import SmaccState

_log = logging.getLogger("smacc_py")


class LifecycleHost(MachinePort, Protocol):
    """The machine as entering and leaving a state sees it: the parts built, the stacks kept."""

    model: MachineModel
    params: SmaccEngineParams
    _stack: list[SmaccState]
    _seq: int
    _active_seqs: set[int]
    _reactors: tuple[StateReactor, ...]
    _orthogonals: dict[type[Orthogonal], Orthogonal]
    _orthogonal_list: list[Orthogonal]

    @property
    def _observers(self) -> Sequence[object]:
        """The registered observers (only tested for emptiness here)."""

    def _state_entered(self, state: SmaccState) -> None:
        """Tell every observer ``state`` finished entering."""

    def _state_exited(self, state: SmaccState) -> None:
        """Tell every observer ``state`` finished exiting."""


def _run_hooks(objects: list[Any], hook: str) -> None:
    """Call ``hook`` on each object; log and skip the ones that raise (names built only on error)."""
    for obj in objects:
        try:
            getattr(obj, hook)()
        except Exception:
            _log.exception("%s.%s raised; skipped", type(obj).__name__, hook.replace("_engine_", "on_"))


def _build_parts(sm: LifecycleHost, state: SmaccState) -> None:
    cls = type(state)
    name = cls.__name__
    for bcfg in cls.behavior_configs:
        orthogonal = sm._orthogonals[bcfg.orthogonal]
        try:
            behavior = bcfg.behavior(*bcfg.args, **bcfg.kwargs)
        except Exception:
            _log.exception("%s: building %s failed; behavior skipped", name, bcfg.behavior.__name__)
            continue
        behavior._attach(orthogonal, state)
        orthogonal.behavior_stack[-1].append(behavior)
        state.behaviors.append((orthogonal, behavior))
    for rcfg in sm.model.reactors[cls]:
        try:
            reactor = rcfg.reactor(*rcfg.args, **rcfg.kwargs)
        except Exception:
            _log.exception("%s: building %s failed; reactor skipped", name, rcfg.reactor.__name__)
            continue
        reactor._attach(state, rcfg.output_event, rcfg.input_events)
        state.reactors.append(reactor)
    if state.reactors:
        sm._reactors = sm._reactors + tuple(state.reactors)
    for gcfg in cls.generator_configs:
        try:
            generator = gcfg.generator(*gcfg.args, **gcfg.kwargs)
        except Exception:
            _log.exception("%s: building %s failed; generator skipped", name, gcfg.generator.__name__)
            continue
        generator._attach(state)
        state.generators.append(generator)


def enter_state(sm: LifecycleHost, cls: type[SmaccState]) -> SmaccState:
    """Construct and enter ``cls`` as the new innermost active state."""
    stack = sm._stack
    sm._seq += 1
    state = cls(sm, stack[-1] if stack else None, sm._seq)
    stack.append(state)
    sm._active_seqs.add(state.seq)
    for orthogonal in sm._orthogonal_list:
        orthogonal.behavior_stack.append([])
    has_parts = bool(cls.behavior_configs or cls.reactor_configs or cls.generator_configs)
    if has_parts:
        _build_parts(sm, state)
    try:
        state.runtime_configure()
    except Exception:
        _log.exception("%s.runtime_configure raised; skipped", cls.__name__)
    if has_parts:
        behaviors = [b for _, b in state.behaviors]
        _run_hooks(behaviors, "runtime_configure")
    try:
        state.on_entry()
    except Exception:
        _log.exception("%s.on_entry raised; skipped", cls.__name__)
    if has_parts:
        _run_hooks(behaviors, "_engine_entry")
        _run_hooks(state.reactors, "on_entry")
        _run_hooks(state.generators, "on_entry")
    if sm._observers:
        sm._state_entered(state)
    return state


def exit_state(sm: LifecycleHost, state: SmaccState) -> None:
    """Exit the innermost active state ``state`` and pop it (its seq is already inactive)."""
    cls = type(state)
    if state.behaviors or state.reactors or state.generators:
        join_s = sm.params.async_join_timeout_s
        for _, behavior in state.behaviors:
            try:
                behavior._engine_exit(join_s)
            except Exception:
                _log.exception("%s.on_exit raised; skipped", type(behavior).__name__)
        _run_hooks(state.reactors, "on_exit")
        _run_hooks(state.generators, "on_exit")
    try:
        state.on_exit()
    except Exception:
        _log.exception("%s.on_exit raised; skipped", cls.__name__)
    for orthogonal in sm._orthogonal_list:
        orthogonal.behavior_stack.pop()
    sm._stack.pop()
    if state.reactors:
        sm._reactors = tuple(r for r in sm._reactors if r.state is not state)
    if sm._observers:
        sm._state_exited(state)
