"""map_server: serves one occupancy map on /map and through GetMap / LoadMap, as nav2_map_server does.

Why: AMCL, the global costmap and every Nav2 client (RViz, BasicNavigator.changeMap) expect the map
exactly where Nav2 puts it. Reading files is the core's job (``nav_stack.core.map_io``); this node
declares the Nav2 parameters, turns a loaded map into a nav_msgs/OccupancyGrid and schedules it.

Lifecycle (node ``map_server``):
  configure  loads ``yaml_filename``; a missing or malformed file fails the transition with a message
             naming the file and the field (the node stays alive and can be configured again).
  activate   publishes the map on ``topic_name`` (reliable, transient local, depth 1: late joiners
             still receive it).
Services (answered only while active, like Nav2):
  ``map_server/map``       nav_msgs/srv/GetMap: the current map.
  ``map_server/load_map``  nav2_msgs/srv/LoadMap: ``map_url`` is ``file:///abs/path.yaml`` or a plain
                           path; the result code says why a load failed, and the old map stays served.
"""

from __future__ import annotations

from dataclasses import dataclass
from urllib.parse import unquote, urlparse

from lifecycle_msgs.msg import State
from nav2_msgs.srv import LoadMap
from nav_msgs.msg import OccupancyGrid
from nav_msgs.srv import GetMap
from rclpy.publisher import Publisher
from rclpy.service import Service

from nav_stack.core.map_io import LoadMapResult, MapLoadError, OccupancyMap, load_map
from nav_stack.ros.common.conversions import occupancy_msg
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.lifecycle.node import NavLifecycleNode

NODE_NAME = "map_server"


@dataclass(frozen=True)
class MapServerParams:
    """nav2_map_server parameters (Jazzy names and defaults)."""

    yaml_filename: str = ""
    topic_name: str = "map"
    frame_id: str = "map"


def path_from_url(map_url: str) -> str:
    """The file path of a LoadMap ``map_url``: ``file://`` URLs and plain paths are accepted.

    Raises MapLoadError(MAP_DOES_NOT_EXIST) for other schemes (``package://`` needs an ament index,
    which a pip installation does not have).
    """
    parsed = urlparse(map_url)
    if parsed.scheme == "file":
        return unquote(parsed.netloc + parsed.path)
    if parsed.scheme and len(parsed.scheme) > 1:  # one letter would be a Windows drive
        raise MapLoadError(LoadMapResult.MAP_DOES_NOT_EXIST,
                           f"map_url {map_url!r}: unsupported scheme '{parsed.scheme}://' "
                           "(use file:///absolute/path.yaml or a plain path)")
    return map_url


class MapServer(NavLifecycleNode):
    """Loads map_server YAML maps and serves them."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self.params = MapServerParams()
        self.map_msg: OccupancyGrid | None = None
        self._pub: Publisher | None = None
        self._map_services: list[Service] = []

    # -- lifecycle -----------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = declare_dataclass(self, MapServerParams)
        try:
            loaded = load_map(self.params.yaml_filename)
        except MapLoadError as error:
            raise ValueError(f"cannot load yaml_filename {self.params.yaml_filename!r}: "
                             f"{error.message} ({error.code.name})") from error
        self.map_msg = self._to_msg(loaded)
        spec = loaded.spec
        self.get_logger().info(f"Loaded map {self.params.yaml_filename} "
                               f"({spec.width} x {spec.height} cells at {spec.resolution} m)")
        self._pub = self.create_publisher(OccupancyGrid, self.params.topic_name, LATCHED)
        self._map_services = [
            self.create_service(GetMap, f"{NODE_NAME}/map", self._on_get_map),
            self.create_service(LoadMap, f"{NODE_NAME}/load_map", self._on_load_map),
        ]

    def activate(self) -> None:
        self._publish()

    def cleanup(self) -> None:
        for service in self._map_services:
            self.destroy_service(service)
        self._map_services = []
        if self._pub is not None:
            self.destroy_publisher(self._pub)
            self._pub = None
        self.map_msg = None

    # -- helpers -------------------------------------------------------------------------------
    def _active(self) -> bool:
        return bool(self._state_machine.current_state[0] == State.PRIMARY_STATE_ACTIVE)

    def _to_msg(self, loaded: OccupancyMap) -> OccupancyGrid:
        return occupancy_msg(loaded.data, loaded.spec, self.params.frame_id, self.get_clock().now().to_msg())

    def _publish(self) -> None:
        if self._pub is not None and self.map_msg is not None:
            self._pub.publish(self.map_msg)

    # -- services ------------------------------------------------------------------------------
    def _on_get_map(self, request: GetMap.Request, response: GetMap.Response) -> GetMap.Response:
        if not self._active() or self.map_msg is None:
            self.get_logger().warning("Received GetMap request but not in ACTIVE state, ignoring!")
            return response
        response.map = self.map_msg
        return response

    def _on_load_map(self, request: LoadMap.Request, response: LoadMap.Response) -> LoadMap.Response:
        if not self._active():
            self.get_logger().warning("Received LoadMap request but not in ACTIVE state, ignoring!")
            response.result = LoadMap.Response.RESULT_UNDEFINED_FAILURE
            return response
        try:
            loaded = load_map(path_from_url(request.map_url))
        except MapLoadError as error:
            self.get_logger().error(f"LoadMap {request.map_url!r} failed ({error.code.name}): "
                                    f"{error.message}; keeping the current map")
            response.result = int(error.code)
            return response
        except Exception as error:  # an unexpected fault must become a result, not a dead service
            self.get_logger().error(f"LoadMap {request.map_url!r} failed: {error!r}; keeping the current map")
            response.result = LoadMap.Response.RESULT_UNDEFINED_FAILURE
            return response
        self.map_msg = self._to_msg(loaded)
        self._publish()
        self.get_logger().info(f"Loaded map {request.map_url}")
        response.map = self.map_msg
        response.result = LoadMap.Response.RESULT_SUCCESS
        return response


def main(argv: list[str] | None = None) -> int:
    """Run the node; configure it with ``-p yaml_filename:=...`` and a lifecycle manager."""
    return run_nodes(lambda: [MapServer()], argv, role="map_server")


if __name__ == "__main__":
    raise SystemExit(main())
