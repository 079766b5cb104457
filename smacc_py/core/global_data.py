"""The machine's blackboard: SMACC2's ``setGlobalSMData``/``getGlobalSMData`` as a locked name→value map.

Values are reported stringified in ``SmaccStatus.global_variable_values``. SMACC2 recommends keeping
shared data in components (machine lifetime) or superstates (superstate lifetime) instead; this map is
for the small counters and flags that do not deserve either.
"""

from __future__ import annotations

import threading
from typing import Any

from smacc_py.core.errors import SmaccLookupError

MISSING: Any = object()
"""Sentinel: no default was given."""


class GlobalData:
    """Thread-safe name→value map; one per machine (never process-global)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._values: dict[str, Any] = {}

    def set(self, name: str, value: Any) -> None:
        """Store ``value`` under ``name`` (a non-empty string)."""
        if not isinstance(name, str) or not name:
            raise ValueError(f"global SM data name must be a non-empty string, got {name!r}")
        with self._lock:
            self._values[name] = value

    def get(self, name: str, default: Any = MISSING) -> Any:
        """The value under ``name``; ``default`` if given and absent, else SmaccLookupError."""
        with self._lock:
            if name in self._values:
                return self._values[name]
            known = sorted(self._values)
        if default is not MISSING:
            return default
        raise SmaccLookupError(f"no global SM data named {name!r} (known: {', '.join(known) or 'none'})")

    def snapshot(self) -> dict[str, Any]:
        """A copy of the whole map."""
        with self._lock:
            return dict(self._values)

    def as_status(self) -> tuple[list[str], list[str]]:
        """(names, str(values)) sorted by name, as ``SmaccStatus`` reports them."""
        items = sorted(self.snapshot().items())
        return [k for k, _ in items], [str(v) for _, v in items]
