"""Hierarchical blackboard with SubTree remapping, as in BehaviorTree.CPP 4.

Each tree instance owns its blackboards (no process-global state): the main tree has a root
blackboard and every SubTree gets a child one. A child resolves a key in this order:
its own entries; an explicit remapping ``internal → external`` (from ``port="{parent_key}"`` on the
SubTree element) looked up in the parent; with ``_autoremap="true"``, the same key in the parent
(keys starting with ``_`` stay private). ``@key`` always addresses the root blackboard.
Writes follow the same resolution, so a remapped output lands in the parent.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from nav_stack.core.bt.errors import BtRuntimeError

_MISSING: Any = object()


class Blackboard:
    """Key → value store of one tree or subtree scope."""

    def __init__(self, parent: Blackboard | None = None, name: str = "root") -> None:
        self._parent = parent
        self._name = name
        self._storage: dict[str, Any] = {}
        self._remapping: dict[str, str] = {}
        self._autoremap = False

    @property
    def parent(self) -> Blackboard | None:
        """The enclosing scope, None for the root blackboard."""
        return self._parent

    @property
    def name(self) -> str:
        """Scope name for messages (tree ID, or the SubTree's path)."""
        return self._name

    def root(self) -> Blackboard:
        """The outermost blackboard."""
        board = self
        while board._parent is not None:
            board = board._parent
        return board

    def add_remapping(self, internal: str, external: str) -> None:
        """Make ``internal`` in this scope an alias of ``external`` in the parent scope."""
        if self._parent is None:
            raise BtRuntimeError(f"blackboard '{self._name}' has no parent to remap '{internal}' into")
        self._remapping[internal] = external

    def enable_autoremap(self, enabled: bool = True) -> None:
        """Resolve keys missing here in the parent (SubTree ``_autoremap``)."""
        self._autoremap = enabled

    def _owner(self, key: str) -> tuple[Blackboard, str]:
        """The scope and key that store ``key`` (or would store it, for a write)."""
        if key.startswith("@"):
            return self.root(), key[1:]
        if key in self._storage or self._parent is None:
            return self, key
        if key in self._remapping:
            return self._parent._owner(self._remapping[key])
        if self._autoremap and not key.startswith("_"):
            return self._parent._owner(key)
        return self, key

    def get(self, key: str, default: Any = _MISSING) -> Any:
        """Value of ``key``; raises KeyError (naming the scope) unless ``default`` is given."""
        board, real_key = self._owner(key)
        value = board._storage.get(real_key, _MISSING)
        if value is _MISSING:
            if default is not _MISSING:
                return default
            raise KeyError(f"blackboard '{self._name}' has no entry '{key}'")
        return value

    def set(self, key: str, value: Any) -> None:
        """Write ``key`` (through remapping into the owning scope)."""
        board, real_key = self._owner(key)
        board._storage[real_key] = value

    def __contains__(self, key: object) -> bool:
        if not isinstance(key, str):
            return False
        board, real_key = self._owner(key)
        return real_key in board._storage

    def keys(self) -> Iterator[str]:
        """Keys stored in this scope (not the parent's)."""
        return iter(sorted(self._storage))

    def items(self) -> dict[str, Any]:
        """A copy of the entries stored in this scope, for display and debugging."""
        return dict(self._storage)
