"""The viewer's HTTP side (stdlib only): the page, a Server-Sent Events stream, and click endpoints.

* ``GET /`` and ``GET /static/<file>``: the self-contained page (no CDN, no build step).
* ``GET /events``: ``text/event-stream``. Each event is one JSON batch
  ``{"t": <server monotonic s>, "layers": {key: value, ...}}`` holding every layer that changed since
  the stream's previous batch; batches are at least ``1 / rate`` s apart. A new stream first gets
  every layer. Nothing is queued per stream: it reads the hub's latest versions (see ``hub``).
* ``GET /api/state``: every layer's current value as one JSON object (debugging, scripts).
* ``POST /api/initial_pose`` and ``POST /api/goal`` with ``{"x": m, "y": m, "yaw": rad}`` (display
  frame) publish RViz's "2D Pose Estimate" and "Nav2 Goal".

Requests whose Host header is not a loopback name (or the bound host) are refused, so a web page
elsewhere cannot reach the robot through DNS rebinding; JSON-only POSTs need a CORS preflight the
server never grants, so other origins cannot click either.
"""

from __future__ import annotations

import json
import logging
import math
import mimetypes
import time
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any, Protocol

from navsuite_tools.viewer.hub import LayerHub, Throttle

STATIC = Path(__file__).resolve().parent / "static"
_LOG = logging.getLogger(__name__)
_LOCAL_HOSTS = {"127.0.0.1", "localhost", "[::1]", "::1"}
_MAX_BODY = 4096


class Commands(Protocol):
    """What the page can ask the robot to do (implemented by ViewerNode)."""

    def publish_initial_pose(self, x: float, y: float, yaw: float) -> object: ...

    def publish_goal(self, x: float, y: float, yaw: float) -> object: ...


def _host_name(header: str) -> str:
    """The name part of a Host header: ``127.0.0.1:8080`` → ``127.0.0.1``, ``[::1]:80`` → ``[::1]``."""
    return header.split("]")[0] + "]" if header.startswith("[") else header.split(":")[0]


class ViewerServer(ThreadingHTTPServer):
    """A threading HTTP server holding the hub, the command sink and the stream settings."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self, host: str, port: int, hub: LayerHub, commands: Commands, rate: float,
                 keepalive: float = 10.0) -> None:
        self.hub = hub
        self.commands = commands
        self.rate = rate
        self.keepalive = keepalive
        Throttle(rate)  # validates the rate before a socket is bound
        super().__init__((host, port), ViewerHandler)

    @property
    def url(self) -> str:
        host, port = str(self.server_address[0]), int(self.server_address[1])
        return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"

    def close(self) -> None:
        """End every stream, stop serving and release the socket."""
        self.hub.close()
        self.shutdown()
        self.server_close()


class ViewerHandler(BaseHTTPRequestHandler):
    server: ViewerServer
    protocol_version = "HTTP/1.1"

    def log_message(self, format: str, *args: Any) -> None:
        _LOG.debug("%s " + format, self.address_string(), *args)

    # ---------------------------------------------------------------- routing
    def do_GET(self) -> None:
        if not self._host_allowed():
            return
        route = self.path.split("?", 1)[0]
        if route in ("/", "/index.html"):
            self._static("index.html")
        elif route.startswith("/static/"):
            self._static(route[len("/static/"):])
        elif route == "/events":
            self._stream()
        elif route == "/api/state":
            self._json(HTTPStatus.OK, self.server.hub.snapshot())
        else:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such page: {route}"})

    def do_POST(self) -> None:
        if not self._host_allowed():
            return
        route = self.path.split("?", 1)[0]
        actions = {"/api/initial_pose": ("/initialpose", self.server.commands.publish_initial_pose),
                   "/api/goal": ("/goal_pose", self.server.commands.publish_goal)}
        if route not in actions:
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such endpoint: {route}"})
            return
        try:
            x, y, yaw = self._pose_body()
        except ValueError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)})
            return
        topic, publish = actions[route]
        publish(x, y, yaw)
        self._json(HTTPStatus.OK, {"ok": True, "topic": topic, "pose": [x, y, yaw]})

    # ---------------------------------------------------------------- pieces
    def _host_allowed(self) -> bool:
        host = _host_name(self.headers.get("Host") or "")
        bound = str(self.server.server_address[0])
        if host in _LOCAL_HOSTS or host == bound or bound in ("0.0.0.0", "::"):
            return True
        self._json(HTTPStatus.FORBIDDEN, {"error": f"host {host!r} not allowed"})
        return False

    def _pose_body(self) -> tuple[float, float, float]:
        if "json" not in (self.headers.get("Content-Type") or ""):
            raise ValueError("body must be application/json")
        length = int(self.headers.get("Content-Length") or 0)
        if not 0 < length <= _MAX_BODY:
            raise ValueError(f"body length must be 1..{_MAX_BODY} bytes, got {length}")
        try:
            body = json.loads(self.rfile.read(length))
        except json.JSONDecodeError as exc:
            raise ValueError(f"body is not JSON: {exc}") from None
        if not isinstance(body, dict):
            raise ValueError("body must be an object {x, y, yaw}")
        values = []
        for key in ("x", "y", "yaw"):
            v = body.get(key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"field {key!r} must be a finite number, got {v!r}")
            values.append(float(v))
        return values[0], values[1], values[2]

    def _json(self, status: HTTPStatus, value: object) -> None:
        body = json.dumps(value).encode()
        self.send_response(status)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def _static(self, name: str) -> None:
        path = (STATIC / name).resolve()
        if STATIC not in path.parents or not path.is_file():
            self._json(HTTPStatus.NOT_FOUND, {"error": f"no such file: {name}"})
            return
        body = path.read_bytes()
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", mimetypes.guess_type(path.name)[0] or "application/octet-stream")
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-cache")
        self.end_headers()
        self.wfile.write(body)

    def _stream(self) -> None:
        """Send batches of changed layers until the client goes away or the server closes."""
        hub, throttle = self.server.hub, Throttle(self.server.rate)
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", "text/event-stream")
        self.send_header("Cache-Control", "no-store")
        self.send_header("Connection", "close")
        self.end_headers()
        self.close_connection = True
        seen: dict[str, int] = {}
        seen_version = 0
        try:
            self.wfile.write(b"retry: 1000\n\n")
            self.wfile.flush()
            while not hub.closed:
                if not hub.wait(seen_version, self.server.keepalive):
                    self.wfile.write(b": keepalive\n\n")
                    self.wfile.flush()
                    continue
                time.sleep(throttle.delay())  # coalesce: whatever arrives meanwhile goes in this batch
                seen_version = hub.version
                parts = [f"{json.dumps(key)}:{text}" for key, text in hub.changed(seen)]
                if not parts:
                    continue
                sent_at = throttle.mark()
                batch = '{"t":' + f"{sent_at:.6f}" + ',"layers":{' + ",".join(parts) + "}}"
                self.wfile.write(f"data: {batch}\n\n".encode())
                self.wfile.flush()
        except (BrokenPipeError, ConnectionResetError, TimeoutError):
            pass  # the tab was closed
