"""map_saver: save a published OccupancyGrid as a map_server map (pgm + yaml), as a service and a CLI.

Why: SLAM and exploration end with "save the map"; Nav2 users do it with the ``map_saver/save_map``
service (nav2_msgs/srv/SaveMap) or ``map_saver_cli -f my_map``. Both are here, with Nav2's options.

The pixel encoding (trinary, scale, raw) and the file writing live in the core,
:func:`nav_stack.core.map_io.save_map`, whose yaml keeps unknown cells unknown on reload (unlike
Nav2's); this module adds the ROS surface, request validation and URL handling.

Only pgm is written (png/bmp would need an image library); other formats are refused with an error
naming the format. Existing files are never overwritten unless asked (service: never; CLI: --overwrite).

The service never blocks its executor: a request subscribes to the map topic and is answered from
the map callback, or by a one-shot timer after ``save_map_timeout`` s of a steady clock (a safety net
for a topic nobody publishes, which must hold even when the simulation, and so sim time, has stopped).
Why no coroutine: rclpy's EventsExecutor sends a service callback's return value at once (an ``async
def`` callback fails), and it re-polls a coroutine awaiting a future without pause (measured: 1.1 s
of CPU for a 2 s wait). :func:`serve_deferred` lets a callback return a Future of its response instead.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.service import Service
from rclpy.task import Future

from nav_stack.core import map_io
from nav_stack.core.map_io import MapMode, OccupancyMap
from nav_stack.ros.common.conversions import grid_from_occupancy
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.runtime.executor import add_executor_argument
from ros_tools.runtime.runner import run_nodes, split_runner_flags
from ros_tools.runtime.waiting import steady_clock

NODE_NAME = "map_saver"
FORMATS = ("pgm",)


@dataclass(frozen=True)
class MapSaverParams:
    """nav2_map_server map_saver parameters (Jazzy names and defaults)."""

    save_map_timeout: float = 2.0  # s to wait for a map message
    free_thresh_default: float = 0.25
    occupied_thresh_default: float = 0.65
    map_subscribe_transient_local: bool = True


@dataclass(frozen=True)
class SaveRequest:
    """What to save and how; ``check()`` raises ValueError naming a bad field."""

    map_url: str = "map"
    image_format: str = "pgm"
    map_mode: str = "trinary"
    free_thresh: float = 0.25
    occupied_thresh: float = 0.65

    def check(self) -> None:
        if self.image_format.lower() not in FORMATS:
            raise ValueError(f"image_format {self.image_format!r} is not supported: only pgm can be written "
                             "(png/bmp need an image library this installation does not have)")
        if self.map_mode not in {m.value for m in MapMode}:
            raise ValueError(f"map_mode {self.map_mode!r} must be trinary, scale or raw")
        if not 0.0 <= self.free_thresh < self.occupied_thresh <= 1.0:
            raise ValueError(f"need 0 <= free_thresh < occupied_thresh <= 1, got free_thresh="
                             f"{self.free_thresh}, occupied_thresh={self.occupied_thresh}")


def map_paths(map_url: str) -> tuple[Path, Path]:
    """(pgm, yaml) paths for a base name (an extension .pgm/.yaml given by the user is dropped)."""
    base = Path(map_url or "map")
    if base.suffix in (".pgm", ".yaml", ".yml"):
        base = base.with_suffix("")
    return base.with_name(base.name + ".pgm"), base.with_name(base.name + ".yaml")


def save_map(occupancy: OccupancyMap, request: SaveRequest, overwrite: bool = False) -> tuple[Path, Path]:
    """Check the request and write the pgm and yaml with the core's writer; returns (pgm, yaml)."""
    request.check()
    pgm_path, _ = map_paths(request.map_url)
    try:
        yaml_path, pgm_path = map_io.save_map(
            occupancy, pgm_path.with_suffix(""), mode=MapMode(request.map_mode),
            free_thresh=request.free_thresh, occupied_thresh=request.occupied_thresh, overwrite=overwrite,
        )
    except FileExistsError as error:
        raise FileExistsError(f"{error} (use --overwrite)") from error
    return pgm_path, yaml_path


def map_qos(transient_local: bool) -> QoSProfile:
    durability = DurabilityPolicy.TRANSIENT_LOCAL if transient_local else DurabilityPolicy.VOLATILE
    return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=durability)


def serve_deferred(node: Node, srv_type: Any, name: str, handler: Callable[[Any, Any], Any]) -> Service:
    """A service whose ``handler(request, response)`` may return a Future of the response, on any executor.

    The client is answered when that future completes (from whichever callback completes it), so the
    handler returns at once and nothing waits. A plain response is sent at once, as usual.
    """
    service = node.create_service(srv_type, name, handler)
    send_now = service.send_response

    def send_response(response: Any, header: Any) -> None:
        if isinstance(response, Future):
            response.add_done_callback(lambda done: send_now(done.result(), header))
        else:
            send_now(response, header)

    setattr(service, "send_response", send_response)  # noqa: B010 - an instance override, on purpose
    return service


class MapSaver(NavLifecycleNode):
    """Lifecycle node ``map_saver`` serving ``map_saver/save_map`` once configured."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self.params = MapSaverParams()
        self._service: Service | None = None

    def configure(self) -> None:
        self.params = declare_dataclass(self, MapSaverParams)
        self._service = serve_deferred(self, SaveMap, f"{NODE_NAME}/save_map", self._on_save)

    def cleanup(self) -> None:
        if self._service is not None:
            self.destroy_service(self._service)
            self._service = None

    def _on_save(self, request: SaveMap.Request, response: SaveMap.Response) -> Future:
        """Check the request, then answer from the first map message or from the timeout timer."""
        p = self.params
        save = SaveRequest(request.map_url or "map", request.image_format or "pgm",
                           request.map_mode or "trinary", float(request.free_thresh) or p.free_thresh_default,
                           float(request.occupied_thresh) or p.occupied_thresh_default)
        topic = request.map_topic or "map"
        answer: Future = Future()
        try:
            save.check()
        except ValueError as error:
            answer.set_result(self._answer(response, error))
            return answer
        entities: list[Any] = []

        def finish(msg: OccupancyGrid | None) -> None:
            if answer.done():
                return
            self.destroy_subscription(entities[0])
            self.destroy_timer(entities[1])
            try:
                if msg is None:
                    raise TimeoutError(f"no map received on '{topic}' within {p.save_map_timeout:.1f} s")
                data, spec = grid_from_occupancy(msg)
                pgm, _ = save_map(OccupancyMap(data, spec), save)
            except (ValueError, OSError, TimeoutError) as error:
                answer.set_result(self._answer(response, error))
                return
            self.get_logger().info(f"Map saved successfully to {pgm} and its yaml")
            answer.set_result(self._answer(response, None))

        entities.append(self.create_subscription(OccupancyGrid, topic, finish,
                                                 map_qos(p.map_subscribe_transient_local)))
        entities.append(self.create_timer(p.save_map_timeout, lambda: finish(None), clock=steady_clock()))
        return answer

    def _answer(self, response: SaveMap.Response, error: Exception | None) -> SaveMap.Response:
        if error is not None:
            self.get_logger().error(f"Failed to save the map: {error}")
        response.result = error is None
        return response


def main(argv: list[str] | None = None) -> int:
    """Run the ``map_saver`` lifecycle node: ``[--autostart] [--executor events|single] [--ros-args ...]``
    (without ``--autostart`` a lifecycle manager configures it)."""

    autostart, executor, rclpy_args = split_runner_flags(sys.argv if argv is None else argv, __doc__)
    return run_nodes(lambda: [MapSaver()], role="map_saver", rclpy_args=rclpy_args, executor=executor,
                     autostart=autostart)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="map_saver_cli", description="Save the map published on a topic.")
    parser.add_argument("-f", dest="map_url", default="map", help="base name of the map files (default: map)")
    parser.add_argument("-t", dest="map_topic", default="map", help="map topic (default: map)")
    parser.add_argument("--occ", type=float, default=0.65, help="occupied threshold (default 0.65)")
    parser.add_argument("--free", type=float, default=0.25, help="free threshold (default 0.25)")
    parser.add_argument("--fmt", default="pgm", help="image format (only pgm)")
    parser.add_argument("--mode", default="trinary", help="trinary (default), scale or raw")
    parser.add_argument("--overwrite", action="store_true", help="replace existing files")
    parser.add_argument("--timeout", type=float, default=5.0, help="s to wait for the map (default 5)")
    add_executor_argument(parser)
    return parser


def cli_main(argv: list[str] | None = None) -> int:
    """``map_saver_cli -f my_map [--occ 0.65] [--free 0.25] [-t map] [--fmt pgm] [--mode trinary]``."""
    args_in = sys.argv[1:] if argv is None else argv
    ros_args: list[str] = []
    if "--ros-args" in args_in:
        split = args_in.index("--ros-args")
        args_in, ros_args = args_in[:split], args_in[split:]
    args = _parser().parse_args(args_in)
    request = SaveRequest(args.map_url, args.fmt, args.mode, args.free, args.occ)
    try:
        request.check()
        for path in map_paths(args.map_url):
            if path.exists() and not args.overwrite:
                raise FileExistsError(f"{path} exists; refusing to overwrite it (use --overwrite)")
    except (ValueError, FileExistsError) as error:
        print(f"map_saver_cli: error: {error}", file=sys.stderr)
        return 2
    received: list[OccupancyGrid] = []
    deadline: list[float] = []  # node-clock s by which the map must have come (set at the first check)

    def build() -> list[Node]:
        node = Node("map_saver_cli")
        node.create_subscription(OccupancyGrid, args.map_topic, received.append, map_qos(True))
        return [node]

    def finished(nodes: Sequence[Any]) -> int | None:
        """Checked between callbacks: save the first map that came, or give up at the deadline."""
        now = nodes[0].get_clock().now().nanoseconds * 1e-9
        deadline[:] = deadline or [now + args.timeout]
        if not received:
            if now < deadline[0]:
                return None
            print(f"map_saver_cli: error: no map received on '{args.map_topic}' within {args.timeout:.1f} s",
                  file=sys.stderr)
            return 1
        try:
            data, spec = grid_from_occupancy(received[-1])
            pgm, yaml_path = save_map(OccupancyMap(data, spec), request, overwrite=args.overwrite)
        except (ValueError, OSError) as error:
            print(f"map_saver_cli: error: {error}", file=sys.stderr)
            return 1
        print(f"map_saver_cli: saved {pgm} and {yaml_path}")
        return 0

    return run_nodes(build, role="map_saver_cli", rclpy_args=["map_saver_cli", *ros_args],
                     executor=args.executor, finished=finished, interrupted_code=130, lockstep=False)


if __name__ == "__main__":
    sys.exit(cli_main())
