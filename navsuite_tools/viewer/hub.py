"""The latest value of every layer, versioned, shared between ROS callbacks and browser streams.

Why this shape: the simulation can run many times faster than real time, so topics may arrive at
kHz rates while a browser needs ~10 updates a second. A ROS callback therefore only stores a cheap
*producer* (usually a closure over the received message) and bumps the layer's version; nothing is
converted or queued per message. Each stream asks for the layers whose version moved since its last
send, so a layer updated 100 times between two sends costs one conversion and one payload. The JSON
text of a version is built once, on first demand, and shared by every stream.

A layer may pass a ``digest`` (a hash of its content): publishing the same digest again is ignored,
so a map republished unchanged is never re-sent.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable, Hashable, Iterator
from dataclasses import dataclass, field

_LOG = logging.getLogger(__name__)

#: Builds a layer's JSON-ready value (dicts, lists, numbers, strings) when a stream needs it.
Producer = Callable[[], object]


@dataclass
class _Layer:
    version: int
    produce: Producer
    digest: Hashable | None
    text: str | None = None
    lock: threading.Lock = field(default_factory=threading.Lock)


class LayerHub:
    """Thread-safe store of versioned layers with a condition streams can wait on."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._layers: dict[str, _Layer] = {}
        self._version = 0
        self._closed = False

    @property
    def version(self) -> int:
        """The newest version of any layer (0 before the first publish)."""
        with self._cond:
            return self._version

    @property
    def closed(self) -> bool:
        return self._closed

    def publish(self, key: str, produce: Producer, digest: Hashable | None = None) -> bool:
        """Make ``produce`` the layer's new value; False (nothing changes) if ``digest`` is unchanged."""
        with self._cond:
            layer = self._layers.get(key)
            if layer is not None and digest is not None and layer.digest == digest:
                return False
            self._version += 1
            self._layers[key] = _Layer(self._version, produce, digest)
            self._cond.notify_all()
            return True

    def wait(self, seen: int, timeout: float) -> bool:
        """Block until some layer is newer than version ``seen`` (True) or ``timeout`` s pass / close."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while self._version <= seen and not self._closed:
                remaining = deadline - time.monotonic()
                if remaining <= 0.0:
                    return False
                self._cond.wait(remaining)
            return self._version > seen

    def changed(self, seen: dict[str, int]) -> Iterator[tuple[str, str]]:
        """Yield ``(key, json_text)`` for each layer newer than ``seen[key]``, updating ``seen``."""
        with self._cond:
            pending = [(key, layer) for key, layer in self._layers.items()
                       if layer.version > seen.get(key, 0)]
        for key, layer in pending:
            seen[key] = layer.version
            yield key, self._text(key, layer)

    def snapshot(self) -> dict[str, object]:
        """Every layer's current value (for GET /api/state and tests)."""
        return {key: json.loads(text) for key, text in self.changed({})}

    def close(self) -> None:
        """Wake every waiting stream so it can end (server shutdown)."""
        with self._cond:
            self._closed = True
            self._cond.notify_all()

    @staticmethod
    def _text(key: str, layer: _Layer) -> str:
        with layer.lock:
            if layer.text is None:
                try:  # NaN/inf are not JSON: producers map them to null, and a slip shows as an error
                    layer.text = json.dumps(layer.produce(), separators=(",", ":"), allow_nan=False)
                except Exception as exc:  # a bad message must not kill the stream: show the error instead
                    _LOG.warning("viewer layer %s: %s", key, exc)
                    layer.text = json.dumps({"error": f"{type(exc).__name__}: {exc}"})
            return layer.text


class Throttle:
    """Spaces sends at least ``1 / rate`` s apart (monotonic clock); each stream owns one."""

    def __init__(self, rate: float, clock: Callable[[], float] = time.monotonic) -> None:
        if not rate > 0.0:
            raise ValueError(f"viewer rate must be > 0 Hz, got {rate!r}")
        self.period = 1.0 / rate
        self._clock = clock
        self._last = -float("inf")

    def delay(self) -> float:
        """Seconds to wait before the next send is allowed (0 if it may go now)."""
        return max(0.0, self._last + self.period - self._clock())

    def mark(self) -> float:
        """Record a send now; returns the send time."""
        self._last = self._clock()
        return self._last
