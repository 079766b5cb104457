"""The registry of declared names: which state classes named which parent, and where each class lives.

Why a registry: a state may name its context by class (``parent=SsPatrol``) or by name
(``parent="SsPatrol"``). A name is resolved only when a machine is compiled, so a machine split across
modules needs no import cycle and superstates and their inner states may come in any order. Until
then the state waits here under the name it gave; the compile binds it to the class for good
(``bind_parent``).

A name matches a class of the same *home* (``home``): the same function body, else the same
top-level package, else the same folder (a module run from a folder), else the same module. So two
packages may each have a ``StState1``, and a test that defines a machine in its body never sees
another test's states.

Everything here is keyed by class objects and names only: the module sits at the bottom of
``smacc_py.core`` (stdlib only), below ``state`` (which registers every SmaccState subclass) and the
machine (which registers itself). Registries of classes are weak where a test may define classes in
a function body and drop them.
"""

from __future__ import annotations

import os
import sys
import weakref

Home = tuple[str, ...]

#: States declared with ``parent="Name"`` and not yet bound to a class, by that name. A machine's compile
#: binds the ones it uses (``bind_parent``), which moves them to their parent's list; defining a state
#: again (a notebook cell run twice) replaces its unbound namesake.
_NAMED_CHILDREN: dict[str, list[type]] = {}
#: Every machine class, so that a ``parent="SmName"`` can be told from a typo (see ``named_parent_orphans``).
_MACHINES: weakref.WeakSet[type] = weakref.WeakSet()
#: Every state class (each SmaccState subclass registers itself), for the same check.
_STATES: weakref.WeakSet[type] = weakref.WeakSet()


def home(cls: type) -> Home:
    """Where a class lives for name resolution: its function body (module and enclosing name) when
    defined in one, else its top-level package, else (a module run from a folder) its folder, else its
    module. Computed once, when first asked (at class creation), so it stays put if the module is
    later removed from ``sys.modules``."""
    found = cls.__dict__.get("_smacc_home")
    if found is None:
        if "<locals>" in cls.__qualname__:
            found = ("scope", cls.__module__, cls.__qualname__.rpartition(".")[0])
        elif "." in cls.__module__:
            found = ("package", cls.__module__.partition(".")[0])
        else:
            path = getattr(sys.modules.get(cls.__module__), "__file__", None)
            found = ("folder", os.path.dirname(os.path.abspath(path))) if path else ("module", cls.__module__)
        type.__setattr__(cls, "_smacc_home", found)
    return found


def register_state(state: type, parent: type | str | None) -> None:
    """Record a state class and the parent it declared (a class, a name or None)."""
    home(state)
    _STATES.add(state)
    if parent is not None:
        _register_child(parent, state)


def register_machine(machine: type) -> None:
    """Record a machine class (SmaccStateMachineBase does, for each subclass)."""
    home(machine)
    _MACHINES.add(machine)


def _register_child(parent: type | str, child: type) -> None:
    if isinstance(parent, str):
        pending = _NAMED_CHILDREN.setdefault(parent, [])
        pending[:] = [c for c in pending if c.__name__ != child.__name__ or home(c) != home(child)]
        pending.append(child)
        return
    children = parent.__dict__.get("_declared_children")
    if children is None:
        children = []
        type.__setattr__(parent, "_declared_children", children)
    children.append(child)


def declared_children(parent: type) -> list[type]:
    """States that named ``parent`` (a machine or a superstate) in their ``parent=`` keyword: by class (or
    by name, once bound), or by name from the same home (``home``) and not yet bound."""
    named = [c for c in _NAMED_CHILDREN.get(parent.__name__, ()) if home(c) == home(parent)]
    return [*parent.__dict__.get("_declared_children", ()), *named]


def bind_parent(child: type, parent: type) -> None:
    """Bind a ``parent="Name"`` to ``parent`` for good, once a machine compiled with it: a factory that
    defines the same classes again (a test building one machine per call) never mixes two calls' states,
    and the state lives as long as its parent, as one declared with ``parent=Class`` does."""
    pending = _NAMED_CHILDREN.get(str(child.__dict__.get("parent_decl")), [])
    if child in pending:
        pending.remove(child)
        _register_child(parent, child)


def named_parent_orphans(where: Home) -> list[type]:
    """States of home ``where`` whose ``parent="Name"`` names no state or machine class of that home."""
    named = [(name, c) for name, children in _NAMED_CHILDREN.items() for c in children if home(c) == where]
    if not named:
        return []
    names = {c.__name__ for c in (*_MACHINES, *_STATES) if home(c) == where}
    return [child for name, child in named if name not in names]
