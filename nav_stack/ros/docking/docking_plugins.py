"""docking_server's dock plugins and dock database on ROS: parameters, topics, the reload service.

Each ``dock_plugins`` entry ``<name>`` is a SimpleChargingDock (``<name>.plugin`` =
``opennav_docking::SimpleChargingDock``, or ``SimpleNonChargingDock`` for docks that do not charge) with
its parameters under ``<name>.``. Its ROS side, as Nav2's plugin has it: it subscribes
``detected_dock_pose`` (geometry_msgs/PoseStamped, with ``use_external_detection_pose``),
``battery_state`` (sensor_msgs/BatteryState, with ``use_battery_status``) and ``joint_states`` (with
``use_stall_detection``), and publishes ``dock_pose``, ``filtered_dock_pose`` and ``staging_pose``
(PoseStamped) for visualisation. Topic names are relative to the server's namespace and shared by
all plugins, as in Nav2.

Dock instances come from the YAML file ``dock_database`` when set, else from the ``docks`` list with
``<dock>.type``, ``<dock>.pose`` [x, y, yaw], ``<dock>.frame`` (map) and ``<dock>.id``; with neither,
docking works by pose only until ``reload_database`` loads a file.
"""

from __future__ import annotations

import math
from typing import Any

from geometry_msgs.msg import PoseStamped
from nav2_msgs.srv import ReloadDockDatabase
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import BatteryState, JointState

from nav_stack.core.docking import (
    SIMPLE_CHARGING_DOCK,
    SIMPLE_NON_CHARGING_DOCK,
    Detection,
    Dock,
    DockDatabase,
    DockDatabaseError,
    SimpleChargingDock,
    SimpleChargingDockParams,
    dock_from_fields,
    load_dock_file,
)
from nav_stack.core.docking.spatial import Pose3D
from nav_stack.core.geometry import Pose2D
from nav_stack.ros.bringup.param_layout import param
from nav_stack.ros.bringup.plugin_catalog import class_name
from nav_stack.ros.common.conversions import pose_stamped
from nav_stack.ros.common.params import declare_dataclass
from ros_tools.tf.ros import stamp_to_seconds

#: Nav2 plugin class → whether it charges.
PLUGIN_TYPES = {SIMPLE_CHARGING_DOCK: True, SIMPLE_NON_CHARGING_DOCK: False}
DETECTION_TOPIC, BATTERY_TOPIC, JOINT_STATES_TOPIC = "detected_dock_pose", "battery_state", "joint_states"
#: Nav2's plugin subscribes with depth 1 (reliable); publishes its poses with depth 1.
DEPTH_1 = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)


def declare_dynamic(node: Node, name: str, default: Any) -> Any:
    """Parameter ``name`` whose type the YAML decides (a list that may be empty, an optional string)."""
    if not node.has_parameter(name):
        node.declare_parameter(name, default, ParameterDescriptor(dynamic_typing=True))
    return node.get_parameter(name).value


class DockPlugin:
    """One dock plugin: its core model and its topics."""

    def __init__(self, node: Node, name: str) -> None:
        self.node, self.name = node, name
        plugin_type = str(param(node, f"{name}.plugin", ""))
        kind = class_name(plugin_type)
        if kind not in PLUGIN_TYPES:
            raise ValueError(f"{node.get_name()}: {name}.plugin '{plugin_type}' is not one of "
                             f"opennav_docking::{{{', '.join(sorted(PLUGIN_TYPES))}}}")
        params = declare_dataclass(node, SimpleChargingDockParams, f"{name}.")
        self.dock = SimpleChargingDock(name, params, is_charger=PLUGIN_TYPES[kind])
        inputs = ((params.use_external_detection_pose, PoseStamped, DETECTION_TOPIC, self._on_detection),
                  (params.use_battery_status and self.dock.is_charger, BatteryState, BATTERY_TOPIC,
                   self._on_battery),
                  (params.use_stall_detection, JointState, JOINT_STATES_TOPIC, self._on_joints))
        self._subs = [node.create_subscription(msg_type, topic, callback, DEPTH_1)
                      for wanted, msg_type, topic, callback in inputs if wanted]
        self._pubs = {topic: node.create_publisher(PoseStamped, topic, DEPTH_1)
                      for topic in ("dock_pose", "filtered_dock_pose", "staging_pose")}
        self._published: dict[str, Any] = {}

    def _on_detection(self, msg: PoseStamped) -> None:
        p, q = msg.pose.position, msg.pose.orientation
        values = (p.x, p.y, p.z, q.x, q.y, q.z, q.w)
        if not all(math.isfinite(v) for v in values) or (q.x, q.y, q.z, q.w) == (0.0, 0.0, 0.0, 0.0):
            self.node.get_logger().warn("ignoring a detected_dock_pose with NaN, inf or a zero quaternion",
                                        throttle_duration_sec=5.0)
            return
        self.dock.on_detection(Detection(Pose3D(*values), msg.header.frame_id.lstrip("/"),
                                         stamp_to_seconds(msg.header.stamp)))

    def _on_battery(self, msg: BatteryState) -> None:
        self.dock.on_battery_current(float(msg.current))

    def _on_joints(self, msg: JointState) -> None:
        self.dock.on_joint_state(list(msg.name), list(msg.velocity), list(msg.effort))

    def publish_updates(self, staging: tuple[Pose2D, str] | None, stamp: Any) -> None:
        """Publish the dock, filtered and staging poses that changed since they were last published."""
        dock = self.dock
        planar = {"dock_pose": (dock.dock_pose, dock.dock_frame) if dock.dock_pose is not None else None,
                  "staging_pose": staging}
        for topic, value in planar.items():
            if value is not None and self._published.get(topic) != value:
                self._published[topic] = value
                self._pubs[topic].publish(pose_stamped(*value[0], value[1], stamp))
        filtered = dock.filtered
        if filtered is not None and self._published.get("filtered_dock_pose") is not filtered:
            self._published["filtered_dock_pose"] = filtered
            self._pubs["filtered_dock_pose"].publish(_pose3d_msg(filtered.pose, filtered.frame, stamp))

    def destroy(self) -> None:
        for sub in self._subs:
            self.node.destroy_subscription(sub)
        for pub in self._pubs.values():
            self.node.destroy_publisher(pub)


def _pose3d_msg(pose: Pose3D, frame: str, stamp: Any) -> PoseStamped:
    msg = PoseStamped()
    msg.header.frame_id, msg.header.stamp = frame, stamp
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = pose.x, pose.y, pose.z
    o = msg.pose.orientation
    o.x, o.y, o.z, o.w = pose.qx, pose.qy, pose.qz, pose.qw
    return msg


def docks_from_parameters(node: Node) -> dict[str, Dock] | None:
    """The dock instances of ``dock_database`` or ``docks`` (None: neither is set).

    Raises:
        ValueError: a dock or the file is malformed (the message names the node, file or parameter).
    """
    path = str(declare_dynamic(node, "dock_database", "") or "")
    try:
        if path:
            node.get_logger().info(f"Loading docks from the database file {path}")
            return load_dock_file(path)
        names = declare_dynamic(node, "docks", [])
        if not names:
            return None
        docks = {}
        for name in names:
            fields = {"type": declare_dynamic(node, f"{name}.type", ""),
                      "pose": list(declare_dynamic(node, f"{name}.pose", [])),
                      "frame": declare_dynamic(node, f"{name}.frame", "map"),
                      "id": declare_dynamic(node, f"{name}.id", "")}
            docks[str(name)] = dock_from_fields(str(name), fields, f"{node.get_name()} parameters")
        return docks
    except DockDatabaseError as error:
        raise ValueError(f"{node.get_name()}: {error}") from error


def reload_handler(node: Node, database: DockDatabase[SimpleChargingDock], busy: Any) -> Any:
    """The ``reload_database`` service callback: replace the docks with a file's (refused while busy)."""

    def reload(request: ReloadDockDatabase.Request, response: ReloadDockDatabase.Response
               ) -> ReloadDockDatabase.Response:
        if busy():
            node.get_logger().error("Cannot reload the dock database while docking or undocking")
            response.success = False
            return response
        try:
            database.reload(load_dock_file(request.filepath))
        except DockDatabaseError as error:
            node.get_logger().error(f"Dock database not reloaded: {error}")
            response.success = False
            return response
        count = len(database.instances)
        node.get_logger().info(f"Dock database reloaded from {request.filepath}: {count} docks")
        response.success = True
        return response

    return reload
