"""The slam node's services: saving the map, pausing, and slam_toolbox's serialize / deserialize.

Why these names: Nav2 and SMACC2 users call slam_toolbox's ``slam_toolbox/serialize_map``,
``slam_toolbox/deserialize_map`` and ``slam_toolbox/pause_new_measurements`` with slam_toolbox's
types (interfaces/slam_toolbox), so the node serves exactly those, relative to its namespace.
``slam/save_map`` and ``slam/pause_new_measurements`` (std_srvs/SetBool) stay: map saving and
smacc_py's CpSlamToolbox use them, and a SetBool names the state it wants where Pause toggles.

  ``slam/save_map`` (nav2_msgs/SaveMap): ``map_url`` is the path without extension, thresholds 0
      mean SAVE_FREE_THRESH / SAVE_OCCUPIED_THRESH; only pgm / trinary are written.
  ``slam/pause_new_measurements`` (std_srvs/SetBool): true ignores scans, false takes them again;
      map and map → odom stay published.
  ``slam_toolbox/pause_new_measurements`` (slam_toolbox/srv/Pause): toggles the same pause;
      ``status`` is true once toggled, as in slam_toolbox (the new state is logged).
  ``slam_toolbox/serialize_map`` (SerializePoseGraph): writes ``<filename>.posegraph`` and
      ``<filename>.data`` (nav_stack/core/slam/serialization.py); ``result`` RESULT_SUCCESS or
      RESULT_FAILED_TO_WRITE_FILE.
  ``slam_toolbox/deserialize_map`` (DeserializePoseGraph): replaces the session by a saved one.
      START_AT_FIRST_NODE / START_AT_GIVEN_POSE continue mapping with the robot at the graph's
      first node / at ``initial_pose`` (map frame); LOCALIZE_AT_POSE localizes on it from
      ``initial_pose`` without changing it. UNSET or a broken file is logged (naming the file and
      field) and the current session goes on. The response is empty, as slam_toolbox's.

Each call runs on the executor thread between scans; a save or a load of a few hundred nodes
takes tens to a few hundred ms (file I/O and re-deriving each scan's points), once per call.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from geometry_msgs.msg import Pose2D as Pose2DMsg
from nav2_msgs.srv import SaveMap
from slam_toolbox.srv import DeserializePoseGraph, Pause, SerializePoseGraph
from std_srvs.srv import SetBool

from nav_stack.core.geometry import Pose2D
from nav_stack.core.map_io import OccupancyMap, save_map
from nav_stack.core.slam import GraphFileError, read_graph, resume, write_graph

if TYPE_CHECKING:
    from nav_stack.ros.slam.slam_node import SlamNode

SAVE_MAP_SERVICE = "~/save_map"
PAUSE_SERVICE = "~/pause_new_measurements"
TOOLBOX_PAUSE_SERVICE = "slam_toolbox/pause_new_measurements"
SERIALIZE_SERVICE = "slam_toolbox/serialize_map"
DESERIALIZE_SERVICE = "slam_toolbox/deserialize_map"
# Thresholds written by save_map when the request leaves them 0. Not Nav2 map_saver's 0.25: with it the
# unknown pixel 205 (occ = 50/255 = 0.196) reloads as *free* (slam_toolbox issue #587); ROS 1's 0.196
# keeps it unknown.
SAVE_FREE_THRESH = 0.196
SAVE_OCCUPIED_THRESH = 0.65
_MATCH_TYPES = {
    DeserializePoseGraph.Request.START_AT_FIRST_NODE: "START_AT_FIRST_NODE",
    DeserializePoseGraph.Request.START_AT_GIVEN_POSE: "START_AT_GIVEN_POSE",
    DeserializePoseGraph.Request.LOCALIZE_AT_POSE: "LOCALIZE_AT_POSE",
}


class SlamServices:
    """The services of one SlamNode; ``create()`` makes them (at configure) and returns them."""

    def __init__(self, node: SlamNode) -> None:
        self.node = node

    def create(self) -> list[object]:
        node = self.node
        return [
            node.create_service(SaveMap, SAVE_MAP_SERVICE, self.on_save_map),
            node.create_service(SetBool, PAUSE_SERVICE, self.on_set_paused),
            node.create_service(Pause, TOOLBOX_PAUSE_SERVICE, self.on_toggle_pause),
            node.create_service(SerializePoseGraph, SERIALIZE_SERVICE, self.on_serialize),
            node.create_service(DeserializePoseGraph, DESERIALIZE_SERVICE, self.on_deserialize),
        ]

    # -- pause -----------------------------------------------------------------------------------
    def set_paused(self, paused: bool) -> str:
        """Pause or resume taking new scans; return the message that was logged."""
        node = self.node
        if paused and not node.paused:
            node.ignored_scans = 0
        elif not paused and node.paused:
            node.get_logger().info(f"ignored {node.ignored_scans} scans while paused")
        node.paused = paused
        message = "new measurements paused" if paused else "new measurements resumed"
        node.get_logger().info(message)
        return message

    def on_set_paused(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        response.message = self.set_paused(bool(request.data))
        response.success = True
        return response

    def on_toggle_pause(self, request: Pause.Request, response: Pause.Response) -> Pause.Response:
        self.set_paused(not self.node.paused)
        response.status = True
        return response

    # -- map and pose graph ----------------------------------------------------------------------
    def on_save_map(self, request: SaveMap.Request, response: SaveMap.Response) -> SaveMap.Response:
        log = self.node.get_logger()
        response.result = False
        image_format = request.image_format.lower() or "pgm"
        mode = request.map_mode.lower() or "trinary"
        if image_format != "pgm" or mode != "trinary":
            log.error(f"save_map: only pgm / trinary maps are written, got image_format="
                      f"{request.image_format!r}, map_mode={request.map_mode!r}")
            return response
        free = request.free_thresh or SAVE_FREE_THRESH
        occupied = request.occupied_thresh or SAVE_OCCUPIED_THRESH
        slam = self.node.slam
        if slam is None or not slam.poses.size:
            log.error("save_map: no map yet (no scan processed)")
            return response
        data, spec = slam.occupancy()
        base = Path(request.map_url or "map").expanduser()
        try:
            yaml_path, _ = save_map(OccupancyMap(data, spec), base, free_thresh=free,
                                    occupied_thresh=occupied, overwrite=True)
        except (OSError, ValueError) as error:
            log.error(f"save_map: cannot write {base}: {error}")
            return response
        log.info(f"save_map: wrote {yaml_path} ({spec.width} x {spec.height} cells)")
        response.result = True
        return response

    def on_serialize(
        self, request: SerializePoseGraph.Request, response: SerializePoseGraph.Response
    ) -> SerializePoseGraph.Response:
        log = self.node.get_logger()
        response.result = SerializePoseGraph.Response.RESULT_FAILED_TO_WRITE_FILE
        slam = self.node.slam
        if slam is None or not slam.poses.size:
            log.error("serialize_map: no pose graph yet (no scan processed)")
            return response
        if not request.filename:
            log.error("serialize_map: the request names no filename")
            return response
        try:
            graph_path, _ = write_graph(slam.graph(), request.filename)
        except OSError as error:
            log.error(f"serialize_map: cannot write {request.filename}: {error}")
            return response
        log.info(f"serialize_map: wrote {graph_path} and its .data ({len(slam.poses)} nodes)")
        response.result = SerializePoseGraph.Response.RESULT_SUCCESS
        return response

    def on_deserialize(
        self, request: DeserializePoseGraph.Request, response: DeserializePoseGraph.Response
    ) -> DeserializePoseGraph.Response:
        log = self.node.get_logger()
        kind = _MATCH_TYPES.get(request.match_type)
        if kind is None:
            log.error(f"deserialize_map: match_type {request.match_type} is not one of "
                      f"{', '.join(f'{v} ({k})' for k, v in _MATCH_TYPES.items())}; nothing loaded")
            return response
        pose: Pose2DMsg = request.initial_pose
        start = None if kind == "START_AT_FIRST_NODE" else Pose2D(pose.x, pose.y, pose.theta)
        try:
            slam = resume(read_graph(request.filename), self.node.params, start, kind == "LOCALIZE_AT_POSE")
        except (GraphFileError, ValueError) as error:
            log.error(f"deserialize_map: {error}; the current session goes on")
            return response
        mode = "localization" if kind == "LOCALIZE_AT_POSE" else "mapping"
        self.node.load_session(slam, f"deserialize_map: loaded {request.filename} ({kind}), {mode}")
        return response
