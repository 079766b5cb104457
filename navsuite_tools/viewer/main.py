"""``navsuite-viewer``: serve the live viewer on loopback with one command.

    navsuite-viewer [--host 127.0.0.1] [--port 8080] [--rate 10] [--frame map] [--sim-time auto]
                    [--executor events|single] [--ros-args ...]

Prints ``viewer: http://HOST:PORT/`` once serving (``--port 0`` picks a free port). Ctrl-C stops it.
DDS stays on this machine unless the user chose ROS_AUTOMATIC_DISCOVERY_RANGE themselves.
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
from collections.abc import Sequence
from typing import Any

from navsuite_tools.viewer.hub import LayerHub
from navsuite_tools.viewer.params import SIM_TIME_MODES, ViewerParams
from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument, make_executor

SPIN_SLICE = 0.1  # wall s the ROS thread serves callbacks between checks of its stop flag


class ViewerApp:
    """The node (spun by its own executor thread) and the HTTP server (its own thread), started together.

    ``context`` is an initialised rclpy Context (tests pass their own); ``close()`` stops both.
    The ROS callbacks only hand messages to the hub; the HTTP threads convert and stream them.
    """

    def __init__(self, params: ViewerParams, context: Any = None) -> None:
        from navsuite_tools.viewer.node import ViewerNode
        from navsuite_tools.viewer.server import ViewerServer

        self.hub = LayerHub()
        self.node = ViewerNode(self.hub, params, context=context)
        self.executor = make_executor(params.executor, context)
        self.executor.add_node(self.node)
        self._stopping = False
        try:
            self.server = ViewerServer(params.host, params.port, self.hub, self.node, params.rate,
                                       params.keepalive)
        except OSError:
            self.node.destroy_node()
            raise
        self._threads = [threading.Thread(target=self._spin, name="viewer-ros", daemon=True),
                         threading.Thread(target=self.server.serve_forever, name="viewer-http", daemon=True)]

    @property
    def url(self) -> str:
        return self.server.url

    def _spin(self) -> None:
        """Serve callbacks in slices until ``close()`` or Ctrl-C / SIGTERM (rclpy shuts the context down).

        Slices, not ``executor.spin()``: on this rclpy the EventsExecutor's spin() without a timeout
        never runs a callback (and holds the GIL); a slice runs every event in C++ and lets the loop
        see the stop flag. A callback that raises is logged and the viewer keeps serving.
        """
        from rclpy.executors import ExternalShutdownException
        from rclpy.task import Future

        while not self._stopping and self.executor.context.ok():
            try:
                self.executor.spin_until_future_complete(Future(), timeout_sec=SPIN_SLICE)
            except ExternalShutdownException:
                return
            except Exception as exc:  # one bad message must not stop the viewer
                if not self.executor.context.ok():
                    return
                self.node.get_logger().error(f"viewer: a callback raised {exc!r}")

    def start(self) -> ViewerApp:
        for thread in self._threads:
            thread.start()
        return self

    def close(self) -> None:
        self.server.close()
        self._stopping = True
        for thread in self._threads:
            thread.join(timeout=5.0)
        self.executor.shutdown(timeout_sec=5.0)
        self.node.destroy_node()


def parse_args(argv: Sequence[str]) -> tuple[ViewerParams, list[str]]:
    """Split ``--ros-args ...`` off and turn the rest into ViewerParams (exit 2 on bad values)."""
    argv = list(argv)
    ros_args = argv[argv.index("--ros-args"):] if "--ros-args" in argv else []
    own = argv[: len(argv) - len(ros_args)]
    defaults = ViewerParams()
    parser = argparse.ArgumentParser(prog="navsuite-viewer",
                                     description="Live browser viewer of the ROS graph.")
    parser.add_argument("--host", default=defaults.host, help="bind address (default: %(default)s, loopback)")
    parser.add_argument("--port", type=int, default=defaults.port, help="TCP port; 0 picks a free one")
    parser.add_argument("--rate", type=float, default=defaults.rate, help="max updates/s per browser (Hz)")
    parser.add_argument("--frame", default=defaults.frame,
                        help="display (fixed) frame (default: map)")
    parser.add_argument("--sim-time", default=defaults.sim_time, choices=SIM_TIME_MODES,
                        help="use /clock for stamps: auto = when a /clock publisher exists")
    add_executor_argument(parser)
    ns = parser.parse_args(own)
    try:
        params = ViewerParams(host=ns.host, port=ns.port, rate=ns.rate, frame=ns.frame, sim_time=ns.sim_time,
                              executor=ns.executor)
    except ValueError as exc:
        parser.error(str(exc))
    return params, ros_args


def main(argv: Sequence[str] | None = None) -> int:
    """Serve until Ctrl-C or SIGTERM (exit 0); 1 when the port cannot be bound.

    The shared runner's process shape (ros_process): rclpy's signal handler off, a signal only raises
    the flag this loop checks, then the app closes while the context is still up. The app spins its
    own node in its own thread, so the main thread only waits here.
    """
    from ros_tools.runtime.runner import ros_process

    params, ros_args = parse_args(sys.argv[1:] if argv is None else argv)
    keep_dds_local()
    with ros_process(["navsuite-viewer", *ros_args]) as process:
        try:
            app = ViewerApp(params).start()
        except OSError as exc:
            print(f"navsuite-viewer: cannot serve on {params.host}:{params.port}: {exc}", file=sys.stderr)
            return 1
        print(f"viewer: {app.url}", flush=True)
        try:
            while process.ok():
                time.sleep(0.2)  # the main thread runs no callback: it only watches the stop flag
        finally:
            app.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
