"""map_saver: save a published OccupancyGrid as a map_server map (pgm + yaml), as a service and a CLI.

Why: SLAM and exploration end with "save the map"; Nav2 users do it with the ``map_saver/save_map``
service (nav2_msgs/srv/SaveMap) or ``map_saver_cli -f my_map``. Both are here, with Nav2's options.

Pixel encoding (nav2 map_io saveMapToFile; cells 0..100, -1 unknown; image row 0 = top):
  trinary  cell ≤ rint(100·free_thresh) → 254, cell ≥ rint(100·occupied_thresh) → 0, otherwise 205.
  scale    known cell c → round(255·(100 − c)/100); unknown → 205 (a pgm has no alpha channel).
  raw      known cell c → c; unknown → 255 (reloads exactly with ``mode: raw``).

The yaml written for trinary differs from Nav2 on purpose: Nav2 writes the classification's
free_thresh (0.25 by default), and map_server then reloads unknown pixels (205 → occupancy 0.196)
as FREE. Here the yaml's free_thresh is min(free_thresh, UNKNOWN_SAFE_FREE_THRESH = 0.196), the value
of the TB3 maps, so 254 (0.004) reloads free, 205 unknown and 0 occupied: the round trip is exact.

Only pgm is written (png/bmp would need an image library); other formats are refused with an error
naming the format. Existing files are never overwritten unless asked (service: never; CLI: --overwrite).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rclpy
import rclpy.context
import yaml
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.service import Service
from rclpy.task import Future

from nav_stack.core.map_io import MapMode, OccupancyMap
from nav_stack.ros.conversions import grid_from_occupancy
from nav_stack.ros.lifecycle import NavLifecycleNode
from nav_stack.ros.lifecycle_manager import wait_for
from nav_stack.ros.params import declare_dataclass

NODE_NAME = "map_saver"
UNKNOWN_SAFE_FREE_THRESH = 0.196  # below 205's occupancy (1 − 205/255 = 0.1961), above 254's (0.0039)
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


def encode_pixels(cells: np.ndarray, mode: MapMode, free_thresh: float, occupied_thresh: float) -> np.ndarray:
    """uint8 image (row 0 = top) of OccupancyGrid cells (row 0 = bottom), per the module docstring."""
    c = cells.astype(np.int16)[::-1]
    known = (c >= 0) & (c <= 100)
    if mode is MapMode.RAW:
        return np.where(known, c, 255).astype(np.uint8)
    if mode is MapMode.SCALE:
        return np.where(known, np.round(255.0 * (100 - c) / 100.0), 205).astype(np.uint8)
    pixels = np.full(c.shape, 205, dtype=np.uint8)
    pixels[known & (c <= round(free_thresh * 100.0))] = 254
    pixels[known & (c >= round(occupied_thresh * 100.0))] = 0
    return pixels


def save_map(occupancy: OccupancyMap, request: SaveRequest, overwrite: bool = False) -> tuple[Path, Path]:
    """Write the pgm and yaml; FileExistsError (naming the path) instead of replacing files."""
    request.check()
    pgm_path, yaml_path = map_paths(request.map_url)
    if not overwrite:
        for path in (pgm_path, yaml_path):
            if path.exists():
                raise FileExistsError(f"{path} exists; refusing to overwrite it (use --overwrite)")
    mode = MapMode(request.map_mode)
    pixels = encode_pixels(occupancy.data, mode, request.free_thresh, request.occupied_thresh)
    spec = occupancy.spec
    header = (f"P5\n# CREATOR: nav_stack map_saver {spec.resolution:.3f} m/pix\n"
              f"{spec.width} {spec.height}\n255\n")
    pgm_path.parent.mkdir(parents=True, exist_ok=True)
    pgm_path.write_bytes(header.encode("ascii") + pixels.tobytes())
    free = request.free_thresh
    if mode is MapMode.TRINARY:
        free = min(free, UNKNOWN_SAFE_FREE_THRESH)
    # OccupancyGrid carries float32 resolution: write its shortest decimal (0.05, not 0.0500000007).
    resolution = float(str(np.float32(spec.resolution)))
    meta = {"image": pgm_path.name, "mode": mode.value, "resolution": resolution,
            "origin": [float(spec.origin_x), float(spec.origin_y), float(spec.origin_yaw)], "negate": 0,
            "occupied_thresh": float(request.occupied_thresh), "free_thresh": float(free)}
    yaml_path.write_text(yaml.safe_dump(meta, sort_keys=False, default_flow_style=None))
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
