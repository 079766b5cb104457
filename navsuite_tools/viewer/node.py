"""The viewer's ROS side: finds layers on the graph, keeps their latest value, publishes clicked poses.

Discovery: every ``discovery_period`` s (wall clock, so a paused simulation does not stop it) the
node lists the graph's topics. A layer topic (``layers.LAYERS``) or a SMACC2 introspection topic
(``<prefix>/smacc/{state_machine_description,status,transition_log}``) gets a subscription once a
publisher of an accepted type exists, with QoS adapted to the publishers like RViz's and
``ros2 topic echo``'s: best effort if any publisher is, transient local only if all are. So the map
(transient local), the particle cloud (best effort) and whatever QoS another stack chose all connect.

The collision monitor's zones have topics of the user's naming (``polygon_pub_topic``), so any
PolygonStamped topic whose publisher is the node ``collision_monitor`` joins the one
``collision_polygons`` layer (the latest outline per topic).

Callbacks never convert: they hand the message to the hub as a lazy producer (latest value only).
Event topics (transitions, behavior tree logs) are folded into monitors so no event is lost.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from navsuite_tools.viewer import layers
from navsuite_tools.viewer.hub import LayerHub
from navsuite_tools.viewer.monitors import BtEvent, BtMonitor, SmaccMonitor, StateInfo, TransitionInfo
from navsuite_tools.viewer.params import ViewerParams
from ros_tools.geometry import set_yaw
from ros_tools.tf.ros import TransformListener
from ros_tools.types import import_type

#: RViz's "2D Pose Estimate" covariance: x, y variance 0.25 m², yaw variance (π/12)² rad².
INITIAL_POSE_COVARIANCE = {0: 0.25, 7: 0.25, 35: 0.06853891945200942}
CLICK_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)  # what RViz's tools publish with
SMACC_TOPIC = re.compile(r"^(?P<sm>.*)/smacc/(?P<kind>state_machine_description|status|transition_log)$")
SMACC_TYPES = {"state_machine_description": "smacc2_msgs/msg/SmaccStateMachine",
               "status": "smacc2_msgs/msg/SmaccStatus",
               "transition_log": "smacc2_msgs/msg/SmaccTransitionLogEntry"}
BT_LOG = ("/behavior_tree_log", "nav2_msgs/msg/BehaviorTreeLog")
BT_STRUCTURE = ("/behavior_tree_structure", "std_msgs/msg/String")


def adapted_qos(publishers: list[Any], depth: int) -> QoSProfile:
    """A subscription QoS compatible with every publisher in ``publishers`` (TopicEndpointInfo list)."""
    profiles = [p.qos_profile for p in publishers]
    best_effort = any(q.reliability == ReliabilityPolicy.BEST_EFFORT for q in profiles)
    latched = bool(profiles) and all(q.durability == DurabilityPolicy.TRANSIENT_LOCAL for q in profiles)
    return QoSProfile(
        depth=depth,
        reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def _seconds(stamp: Any) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


class ViewerNode(Node):
    """Subscribes to whatever layers exist and feeds ``hub``; publishes /initialpose and /goal_pose."""

    def __init__(self, hub: LayerHub, params: ViewerParams | None = None, **kwargs: Any) -> None:
        super().__init__("viewer", **kwargs)
        self.params = params or ViewerParams()
        self.hub = hub
        self.tf = TransformListener(self)
        self.frames = layers.DisplayFrames(self.tf.buffer, self.params.frame)
        self.bt = BtMonitor()
        self.machines: dict[str, SmaccMonitor] = {}
        self._subscribed: dict[str, dict[str, object]] = {}  # topic → info shown on the page
        self._subs: list[Any] = []
        self._zones: dict[str, Any] = {}  # collision-monitor zone topic → its latest PolygonStamped
        self._pub_initial = self.create_publisher(PoseWithCovarianceStamped, "/initialpose", CLICK_QOS)
        self._pub_goal = self.create_publisher(PoseStamped, "/goal_pose", CLICK_QOS)
        self._publish_info()
        self.create_timer(self.params.discovery_period, self.discover,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.discover()

    # ---------------------------------------------------------------- discovery
    def discover(self) -> None:
        """Subscribe to every wanted topic that now has a publisher of an accepted type."""
        graph = dict(self.get_topic_names_and_types())
        if self.params.sim_time == "auto" and "/clock" in graph and not self._uses_sim_time():
            self.set_parameters([Parameter("use_sim_time", value=True)])
            self.get_logger().info("viewer: /clock found, stamping clicked poses with simulation time")
        for spec in layers.LAYERS:
            self._try_subscribe(graph, spec.topic, spec.types, self._layer_callback(spec), depth=1)
        for topic in self._zone_topics(graph):
            self._try_subscribe(graph, topic, layers.POLYGON_TYPE, functools.partial(self._on_zone, topic), 1)
        self._try_subscribe(graph, *BT_LOG, self._on_bt_log, depth=50)
        self._try_subscribe(graph, *BT_STRUCTURE, self._on_bt_structure, depth=1)
        for topic in graph:
            match = SMACC_TOPIC.match(topic)
            if match:
                sm, kind = match["sm"] or "/", match["kind"]
                handler = {"state_machine_description": self._on_smacc_state_machine_description,
                           "status": self._on_smacc_status,
                           "transition_log": self._on_smacc_transition_log}[kind]
                self._try_subscribe(graph, topic, (SMACC_TYPES[kind],), functools.partial(handler, sm),
                                    depth=50 if kind == "transition_log" else 1)

    def _zone_topics(self, graph: dict[str, list[str]]) -> list[str]:
        """PolygonStamped topics the collision monitor publishes that are not subscribed yet."""
        return [topic for topic, types in graph.items()
                if layers.POLYGON_TYPE in types and topic not in self._subscribed
                and any(info.node_name == layers.POLYGON_PUBLISHER
                        for info in self.get_publishers_info_by_topic(topic))]

    def _uses_sim_time(self) -> bool:
        return bool(self.get_parameter("use_sim_time").value)

    def _try_subscribe(self, graph: dict[str, list[str]], topic: str, types: tuple[str, ...] | str,
                       callback: Callable[[Any], None], depth: int) -> None:
        types = (types,) if isinstance(types, str) else types
        resolved = self.resolve_topic_name(topic)
        if resolved in self._subscribed or resolved not in graph:
            return
        type_name = next((t for t in types if t in graph[resolved]), None)
        publishers = self.get_publishers_info_by_topic(resolved)
        if type_name is None or not publishers:
            return
        try:
            msg_type = import_type(type_name)
        except ValueError as exc:  # an interface package not built here: skip the layer, say why once
            self._subscribed[resolved] = {"type": type_name, "error": str(exc)}
            self.get_logger().warning(f"viewer: not showing {resolved}: {exc}")
            self._publish_info()
            return
        qos = adapted_qos(publishers, depth)
        self._subs.append(self.create_subscription(msg_type, resolved, callback, qos))
        best_effort = qos.reliability == ReliabilityPolicy.BEST_EFFORT
        latched = qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
        self._subscribed[resolved] = {"type": type_name,
                                      "reliability": "best_effort" if best_effort else "reliable",
                                      "durability": "transient_local" if latched else "volatile"}
        self._publish_info()

    def _publish_info(self) -> None:
        p = self.params
        info = {"frame": p.frame, "robot_radius": p.robot_radius, "rate": p.rate,
                "topics": dict(sorted(self._subscribed.items()))}
        self.hub.publish("info", lambda: info)

    # ---------------------------------------------------------------- callbacks: store, never convert
    def _layer_callback(self, spec: layers.LayerSpec) -> Callable[[Any], None]:
        frames, limit, hub = self.frames, self.params.max_poses, self.hub

        def on_message(msg: Any) -> None:
            digest = spec.digest(msg) if spec.digest else None
            hub.publish(spec.key, lambda: spec.convert(msg, frames, limit), digest)

        return on_message

    def _on_zone(self, topic: str, msg: Any) -> None:
        self._zones[topic] = msg
        zones, frames, limit = dict(self._zones), self.frames, self.params.max_poses
        self.hub.publish(layers.POLYGON_LAYER, lambda: layers.polygons(zones, frames, limit))

    def _on_bt_log(self, msg: Any) -> None:
        self.bt.apply(BtEvent(_seconds(e.timestamp), e.node_name, e.uid, e.previous_status, e.current_status)
                      for e in msg.event_log)
        self.hub.publish("bt", self.bt.snapshot)

    def _on_bt_structure(self, msg: Any) -> None:
        try:
            self.bt.set_structure(msg.data)
        except ValueError as exc:
            self.get_logger().warning(f"viewer: {BT_STRUCTURE[0]}: {exc}")
            return
        self.hub.publish("bt", self.bt.snapshot)

    def _machine(self, sm: str) -> SmaccMonitor:
        if sm not in self.machines:
            self.machines[sm] = SmaccMonitor(sm)
        return self.machines[sm]

    def _publish_machine(self, machine: SmaccMonitor) -> None:
        self.hub.publish(f"sm:{machine.name}", machine.snapshot, digest=machine.revision)

    def _on_smacc_state_machine_description(self, sm: str, msg: Any) -> None:
        machine = self._machine(sm)
        machine.set_description([
            StateInfo(s.name, int(s.level), tuple(s.children_states),
                      tuple(_transition(t, s.name) for t in s.transitions),
                      tuple((o.name, tuple(o.client_behavior_names)) for o in s.orthogonals))
            for s in msg.states])
        self._publish_machine(machine)

    def _on_smacc_status(self, sm: str, msg: Any) -> None:
        machine = self._machine(sm)
        machine.set_status(list(msg.current_states),
                           dict(zip(msg.global_variable_names, msg.global_variable_values, strict=False)))
        self._publish_machine(machine)

    def _on_smacc_transition_log(self, sm: str, msg: Any) -> None:
        machine = self._machine(sm)
        machine.add_transition(_seconds(msg.timestamp), _transition(msg.transition, ""))
        self._publish_machine(machine)

    # ---------------------------------------------------------------- clicks from the page
    def publish_initial_pose(self, x: float, y: float, yaw: float) -> PoseWithCovarianceStamped:
        """RViz's "2D Pose Estimate": a pose in the display frame with RViz's covariance."""
        msg = PoseWithCovarianceStamped()
        self._fill_header(msg, x, y, yaw, msg.pose.pose)
        covariance = [0.0] * 36
        for i, v in INITIAL_POSE_COVARIANCE.items():
            covariance[i] = v
        msg.pose.covariance = covariance
        self._pub_initial.publish(msg)
        return msg

    def publish_goal(self, x: float, y: float, yaw: float) -> PoseStamped:
        """RViz's "Nav2 Goal": a PoseStamped in the display frame on /goal_pose (bt_navigator listens)."""
        msg = PoseStamped()
        self._fill_header(msg, x, y, yaw, msg.pose)
        self._pub_goal.publish(msg)
        return msg

    def _fill_header(self, msg: Any, x: float, y: float, yaw: float, pose: Any) -> None:
        msg.header.frame_id = self.params.frame
        msg.header.stamp = self.get_clock().now().to_msg()
        pose.position.x, pose.position.y = float(x), float(y)
        set_yaw(pose.orientation, yaw)


def _transition(t: Any, state: str) -> TransitionInfo:
    return TransitionInfo(t.source_state_name or state, t.destiny_state_name, t.transition_type,
                          t.transition_name, t.event.event_type)
