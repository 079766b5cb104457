"""map_saver: save a published OccupancyGrid as a map_server map (pgm + yaml), as a service and a CLI.

Why: SLAM and exploration end with "save the map"; Nav2 users do it with the ``map_saver/save_map``
service (nav2_msgs/srv/SaveMap) or ``map_saver_cli -f my_map``. Both are here, with Nav2's options.

The pixel encoding (trinary, scale, raw) and the file writing live in the core,
:func:`nav_stack.core.map_io.save_map`, whose yaml keeps unknown cells unknown on reload (unlike
Nav2's); this module adds the ROS surface, request validation and URL handling.

Only pgm is written (png/bmp would need an image library); other formats are refused with an error
naming the format. Existing files are never overwritten unless asked (service: never; CLI: --overwrite).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import rclpy
import rclpy.context
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.service import Service
from rclpy.task import Future

from nav_stack.core import map_io
from nav_stack.core.map_io import MapMode, OccupancyMap
from nav_stack.ros.conversions import grid_from_occupancy
from nav_stack.ros.lifecycle import NavLifecycleNode
from nav_stack.ros.lifecycle_manager import wait_for
from nav_stack.ros.params import declare_dataclass

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


class MapSaver(NavLifecycleNode):
    """Lifecycle node ``map_saver`` serving ``map_saver/save_map`` once configured."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self.params = MapSaverParams()
        self._service: Service | None = None

    def configure(self) -> None:
        self.params = declare_dataclass(self, MapSaverParams)
        # Reentrant: the handler awaits a subscription and a timer, which must run meanwhile.
        self._group = ReentrantCallbackGroup()
        self._service = self.create_service(SaveMap, f"{NODE_NAME}/save_map", self._on_save,
                                            callback_group=self._group)

    def cleanup(self) -> None:
        if self._service is not None:
            self.destroy_service(self._service)
            self._service = None

    async def _on_save(self, request: SaveMap.Request, response: SaveMap.Response) -> SaveMap.Response:
        p = self.params
        save = SaveRequest(request.map_url or "map", request.image_format or "pgm",
                           request.map_mode or "trinary", float(request.free_thresh) or p.free_thresh_default,
                           float(request.occupied_thresh) or p.occupied_thresh_default)
        topic = request.map_topic or "map"
        received: Future = Future()
        sub = self.create_subscription(OccupancyGrid, topic,
                                       lambda m: received.done() or received.set_result(m),
                                       map_qos(p.map_subscribe_transient_local), callback_group=self._group)
        try:
            save.check()
            if not await wait_for(self, received, p.save_map_timeout, self._group):
                raise TimeoutError(f"no map received on '{topic}' within {p.save_map_timeout:.1f} s")
            data, spec = grid_from_occupancy(received.result())
            pgm, _ = save_map(OccupancyMap(data, spec), save)
        except (ValueError, OSError, TimeoutError) as error:
            self.get_logger().error(f"Failed to save the map: {error}")
            response.result = False
            return response
        finally:
            self.destroy_subscription(sub)
        self.get_logger().info(f"Map saved successfully to {pgm} and its yaml")
        response.result = True
        return response


def main(argv: list[str] | None = None) -> None:
    """Run the ``map_saver`` lifecycle node (configure it with a lifecycle manager)."""
    rclpy.init(args=sys.argv if argv is None else argv)
    node = MapSaver()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


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
    context = rclpy.context.Context()
    rclpy.init(args=["map_saver_cli", *ros_args], context=context)
    node = Node("map_saver_cli", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    received: list[OccupancyGrid] = []
    node.create_subscription(OccupancyGrid, args.map_topic, received.append, map_qos(True))
    try:
        deadline = node.get_clock().now().nanoseconds * 1e-9 + args.timeout
        while not received and node.get_clock().now().nanoseconds * 1e-9 < deadline:
            executor.spin_once(timeout_sec=0.05)
        if not received:
            print(f"map_saver_cli: error: no map received on '{args.map_topic}' within {args.timeout:.1f} s",
                  file=sys.stderr)
            return 1
        data, spec = grid_from_occupancy(received[-1])
        pgm, yaml_path = save_map(OccupancyMap(data, spec), request, overwrite=args.overwrite)
        print(f"map_saver_cli: saved {pgm} and {yaml_path}")
        return 0
    except (ValueError, OSError) as error:
        print(f"map_saver_cli: error: {error}", file=sys.stderr)
        return 1
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=context)


if __name__ == "__main__":
    sys.exit(cli_main())
