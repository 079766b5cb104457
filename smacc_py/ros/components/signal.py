"""``SmaccSignal``: a list of listeners a component calls, like SMACC2's boost::signals2 signals.

Why not post events only: behaviors often want the message itself right away (a predicate, a
counter) without a transition, and SMACC2 gives them ``onMessageReceived(&Cb::fn, this)``. Here a
behavior connects a callable and keeps the returned ``disconnect`` to call in ``on_exit``, so no
listener outlives its state. Listeners run on the thread that emits (the executor thread under the
ROS runtime) and must return quickly.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Generic, TypeVar

_log = logging.getLogger("smacc_py")

T = TypeVar("T")


class SmaccSignal(Generic[T]):
    """Listeners of one kind of news (a message, a timeout), each called with one argument."""

    def __init__(self, name: str) -> None:
        self.name = name
        self._lock = threading.Lock()
        self._listeners: list[Callable[[T], None]] = []

    def connect(self, listener: Callable[[T], None]) -> Callable[[], None]:
        """Call ``listener(value)`` on every emit from now on; returns the function that disconnects it."""
        with self._lock:
            self._listeners.append(listener)
        return lambda: self.disconnect(listener)

    def disconnect(self, listener: Callable[[T], None]) -> None:
        """Stop calling ``listener`` (an equal bound method will do); nothing if it is not connected."""
        with self._lock:
            if listener in self._listeners:
                self._listeners.remove(listener)

    def emit(self, value: T) -> None:
        """Call every listener; one that raises is logged and the others still run."""
        with self._lock:
            listeners = list(self._listeners)
        for listener in listeners:
            try:
                listener(value)
            except Exception:
                _log.exception("a listener of %s raised; skipped", self.name)

    def __len__(self) -> int:
        with self._lock:
            return len(self._listeners)
