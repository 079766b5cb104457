"""A minimal client of the viewer's HTTP API for tests: page fetches, JSON POSTs and an SSE reader."""

from __future__ import annotations

import contextlib
import http.client
import json
import socket
import threading
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable
from typing import Any

from navsuite_testing.ros import wait_until


def get(url: str, timeout: float = 10.0) -> tuple[int, str, str]:
    """GET ``url`` → (status, content type, body text); HTTP errors are returned, not raised."""
    try:
        with urllib.request.urlopen(url, timeout=timeout) as reply:
            return reply.status, reply.headers.get("Content-Type", ""), reply.read().decode()
    except urllib.error.HTTPError as err:
        return err.code, err.headers.get("Content-Type", ""), err.read().decode()


def post_json(url: str, body: object, timeout: float = 10.0) -> tuple[int, dict[str, Any]]:
    """POST ``body`` as JSON → (status, decoded JSON reply)."""
    data = json.dumps(body).encode()
    request = urllib.request.Request(url, data=data, headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=timeout) as reply:
            return reply.status, json.loads(reply.read())
    except urllib.error.HTTPError as err:
        return err.code, json.loads(err.read())


class EventStream:
    """Reads ``GET /events`` in a thread: batches into ``batches``, newest value per layer into ``latest``."""

    def __init__(self, base_url: str) -> None:
        self.batches: list[dict[str, Any]] = []
        self.latest: dict[str, Any] = {}
        self._lock = threading.RLock()  # predicates may call layer_batches()
        parts = urllib.parse.urlsplit(base_url)
        self._connection = http.client.HTTPConnection(parts.hostname, parts.port, timeout=30.0)
        self._connection.request("GET", "/events")
        self._sock = self._connection.sock  # http.client forgets it once a "Connection: close" reply starts
        self._response = self._connection.getresponse()
        self._thread = threading.Thread(target=self._read, daemon=True)
        self._thread.start()

    def _read(self) -> None:
        try:
            for raw in self._response:
                line = raw.decode().rstrip("\n")
                if line.startswith("data: "):
                    batch = json.loads(line[len("data: "):])
                    with self._lock:
                        self.batches.append(batch)
                        self.latest.update(batch["layers"])
        except (OSError, ValueError):
            pass  # closed by the test or the server

    def wait_for(self, predicate: Callable[[dict[str, Any]], bool], timeout: float,
                 what: str) -> dict[str, Any]:
        """Wait until ``predicate(latest)`` holds; returns a copy of ``latest``."""
        def check() -> bool:
            with self._lock:
                return predicate(self.latest)
        wait_until(check, timeout, what)
        with self._lock:
            return dict(self.latest)

    def layer_batches(self, key: str) -> list[dict[str, Any]]:
        with self._lock:
            return [b for b in self.batches if key in b["layers"]]

    def close(self) -> None:
        """Shut the socket down first: it wakes the reader thread blocked in a read."""
        with contextlib.suppress(OSError):
            self._sock.shutdown(socket.SHUT_RDWR)
        self._thread.join(timeout=5.0)
        self._connection.close()
