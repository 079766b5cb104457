"""collision_monitor: Nav2 Jazzy's last safety layer between the velocity smoother and the robot.

In: ``cmd_vel_in_topic`` (``cmd_vel_smoothed``; Twist, or TwistStamped with
``enable_stamped_cmd_vel``), the ``observation_sources`` (LaserScan / PointCloud2, sensor-data QoS),
TF, and for zones shaped by a topic their PolygonStamped (nav_stack.ros.collision.collision_monitor_sources).
Out: ``cmd_vel_out_topic`` (``cmd_vel``) with the input's header when stamped; ``state_topic``
(nav2_msgs/CollisionMonitorState, when named) each time the acting polygon changes;
``~/collision_points_marker`` (visualization_msgs/MarkerArray, while someone listens: one POINTS marker
per source, Jazzy's ``collision_points_<source>``); each zone with ``visualize`` on its
``polygon_pub_topic`` (geometry_msgs/PolygonStamped; default: the zone's name). Both are built by
nav_stack.ros.collision.collision_monitor_markers.

A source whose newest data is older than its ``source_timeout`` (or that never published, or that TF
cannot place) stops the robot as Nav2 does (state ``invalid source``); the warning names the source
and why.

Every input command is decided by nav_stack.core.collision_monitor (which polygon acts, the stop
publication rule); there is no timer: like Nav2, the node works only when a command arrives, and
publishes nothing when the input falls silent. Run-time ``<polygon>.enabled`` and
``<source>.enabled`` changes are taken, as Nav2 takes them.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from geometry_msgs.msg import PolygonStamped, Twist, TwistStamped
from nav2_msgs.msg import CollisionMonitorState
from rcl_interfaces.msg import SetParametersResult
from rclpy.exceptions import InvalidParameterTypeException
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import Header
from visualization_msgs.msg import MarkerArray

from nav_stack.core.collision_monitor import (
    INVALID_SOURCE,
    Action,
    ActionType,
    CollisionMonitor,
    CollisionMonitorParams,
    PolygonParams,
    SourceParams,
    Velocity,
    Zone,
)
from nav_stack.core.geometry import FloatArray
from nav_stack.ros.collision.collision_monitor_markers import collision_points_marker, polygon_stamped
from nav_stack.ros.collision.collision_monitor_sources import ObservationSource, SourceFrames, ZoneShapeInput
from nav_stack.ros.common.frames import Frames
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import DEFAULT
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.cmd_vel import CMD_VEL_QOS, CmdVelPublisher

NODE_NAME = "collision_monitor"
MARKER_TOPIC = "~/collision_points_marker"
WARN_PERIOD = 5.0  # s between two repeats of a warning
_NO_POINTS = np.zeros((0, 2))  # a disabled source's marker


class CollisionMonitorNode(NavLifecycleNode):
    """The ``collision_monitor`` lifecycle node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self._active = False
        self._invalid = ""  # "<source>: <why>" of the source that made the last command stop
        #: (source, reason kind) and steady s of the last invalid-source warning: a new fault is said at
        #: once, the same one again only every WARN_PERIOD (rclpy's per-call-site throttle hid a stale
        #: scan for 5 s when "no data yet" had just been logged)
        self._warned: tuple[tuple[str, str], float] = (("", ""), -math.inf)

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, CollisionMonitorParams)
        if p.use_realtime_priority:
            self.get_logger().warning("use_realtime_priority is accepted and ignored by this port")
        zones = [Zone(name, self._polygon_params(name)) for name in p.polygons]
        source_params = {name: declare_dataclass(self, SourceParams, f"{name}.",
                                                 source_timeout=p.source_timeout)
                         for name in p.observation_sources}
        for zone in zones:
            unknown = [s for s in zone.params.sources_names if s not in source_params]
            if unknown:
                raise ValueError(f"{self.get_name()}: {zone.name}.sources_names = "
                                 f"{list(zone.params.sources_names)} names {', '.join(unknown)}, not in "
                                 f"observation_sources = {list(p.observation_sources)}")
        self.monitor = CollisionMonitor(p, zones)
        self.frames = Frames(self, p.base_frame_id)
        source_frames = SourceFrames(self.frames.listener, p.base_frame_id, p.odom_frame_id,
                                     p.transform_tolerance, p.base_shift_correction)
        self.sources = [ObservationSource(self, name, sp, source_frames)
                        for name, sp in source_params.items()]
        self.shape_inputs = [ZoneShapeInput(self, z, self.frames.listener, p.base_frame_id)
                             for z in zones if z.dynamic]
        self._cmd = CmdVelPublisher(self, p.enable_stamped_cmd_vel, p.base_frame_id, p.cmd_vel_out_topic)
        self._cmd_sub = self.create_subscription(TwistStamped if self._cmd.stamped else Twist,
                                                 p.cmd_vel_in_topic, self._on_command, CMD_VEL_QOS)
        self._state_pub = (self.create_publisher(CollisionMonitorState, p.state_topic, DEFAULT)
                           if p.state_topic else None)
        self._marker_pub = self.create_publisher(MarkerArray, MARKER_TOPIC, DEFAULT)
        self._polygon_pubs = {z.name: self.create_publisher(PolygonStamped, z.params.polygon_pub_topic,
                                                            DEFAULT)
                              for z in zones if z.params.visualize}
        self.add_on_set_parameters_callback(self._on_enabled)

    def _polygon_params(self, name: str) -> PolygonParams:
        """``<name>.*`` as PolygonParams; a Humble/Iron flat ``points`` list gets Jazzy's spelling."""
        try:
            params = declare_dataclass(self, PolygonParams, f"{name}.", polygon_pub_topic=name)
        except InvalidParameterTypeException as error:
            hint = (f". Jazzy takes {name}.points as a string '[[x, y], [x, y], ...]' (the flat list is "
                    "Humble's and Iron's form)") if f"'{name}.points'" in str(error) else ""
            raise ValueError(f"{self.get_name()}: {error}{hint}") from error
        if params.max_points >= 0:
            self.get_logger().warning(f"[{name}]: \"max_points\" is deprecated: use \"min_points\" "
                                      f"(now {params.effective_min_points})")
        return params

    def activate(self) -> None:
        self._publish_polygons()
        self._active = True

    def deactivate(self) -> None:
        self._active = False
        self.monitor.reset()

    def cleanup(self) -> None:
        self.remove_on_set_parameters_callback(self._on_enabled)
        self.destroy_subscription(self._cmd_sub)
        self._cmd.destroy()
        for source in self.sources:
            source.destroy()
        for shape in self.shape_inputs:
            shape.destroy()
        for pub in [self._state_pub, self._marker_pub, *self._polygon_pubs.values()]:
            if pub is not None:
                self.destroy_publisher(pub)
        self.frames.destroy()

    # -- one command -------------------------------------------------------------------------------
    def _on_command(self, msg: Twist | TwistStamped) -> None:
        if not self._active:
            return
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        command = Velocity(twist.linear.x, twist.linear.y, twist.angular.z)
        if not command.finite:
            self.get_logger().error("Velocity message contains NaNs or Infs! Ignoring as invalid!",
                                    throttle_duration_sec=WARN_PERIOD)
            return
        now = self.get_clock().now().nanoseconds * 1e-9
        points = self._collect(now)
        for shape in self.shape_inputs:
            shape.update()
            if shape.zone.enabled and not shape.zone.is_set:
                self.get_logger().warning(f"[{shape.zone.name}]: Polygon shape is not set yet",
                                          throttle_duration_sec=WARN_PERIOD)
        outcome = self.monitor.process(command, points, now)
        if outcome.state_changed:
            self._report(outcome.action)
        if outcome.publish:
            header = msg.header if isinstance(msg, TwistStamped) else Header()
            self._cmd.frame_id = header.frame_id
            velocity, stamp = outcome.action.velocity, header.stamp
            self._cmd.publish(velocity.x, velocity.tw, stamp.sec * 1_000_000_000 + stamp.nanosec,
                              vy=velocity.y)
        self._publish_polygons()

    def _collect(self, now: float) -> dict[str, FloatArray] | None:
        """Each enabled source's points, or None when one is invalid and its timeout is not 0.

        Nav2's order: sources are read in the order of ``observation_sources`` and reading stops at
        the first invalid one; the markers show what was read up to there.
        """
        points: dict[str, FloatArray] = {}
        shown: list[tuple[str, FloatArray]] = []
        self._invalid = ""
        for source in self.sources:
            data = source.points(now) if source.params.enabled else None
            if source.params.enabled and data is None and source.params.source_timeout != 0.0:
                self._invalid = f"{source.name}: {source.reason}"
                self._warn_invalid(source)
                break
            if data is not None:
                points[source.name] = data
            shown.append((source.name, data if data is not None else _NO_POINTS))
        if self._marker_pub.get_subscription_count() > 0:
            self._marker_pub.publish(collision_points_marker(self.params.base_frame_id, shown))
        if not self._invalid:
            self._warned = (("", ""), -math.inf)   # all valid again: the next fault is news
        return None if self._invalid else points

    def _warn_invalid(self, source: ObservationSource) -> None:
        """Say why a source is invalid: at once for a new fault, then every WARN_PERIOD (steady s)."""
        key, now = (source.name, source.reason_kind), time.monotonic()
        if key == self._warned[0] and now - self._warned[1] < WARN_PERIOD:
            return
        self._warned = (key, now)
        self.get_logger().warning(f"[{source.name}]: {source.reason}; ignoring the source: the robot stops")

    # -- outputs -----------------------------------------------------------------------------------
    def _report(self, action: Action) -> None:
        """Log the new state as Nav2 words it and publish it on ``state_topic``."""
        zone = next((z for z in self.monitor.zones if z.name == action.polygon_name), None)
        if action.polygon_name == INVALID_SOURCE:
            self.get_logger().warning(f"Robot to stop due to invalid source ({self._invalid}). Either due to "
                                      "data not published yet, or to lack of new data received within the "
                                      "sensor timeout, or if impossible to transform data to base frame")
        elif zone is None:
            self.get_logger().info("Robot to continue normal operation")
        elif action.action_type == ActionType.SLOWDOWN:
            self.get_logger().info(f"Robot to slowdown for {zone.params.slowdown_ratio * 100:f} percents "
                                   f"due to {zone.name} polygon")
        elif action.action_type == ActionType.APPROACH:
            self.get_logger().info(f"Robot to approach for {zone.params.time_before_collision:f} seconds "
                                   "away from collision")
        else:
            verb = "stop" if action.action_type == ActionType.STOP else "limit speed"
            self.get_logger().info(f"Robot to {verb} due to {zone.name} polygon")
        if self._state_pub is not None:
            self._state_pub.publish(CollisionMonitorState(action_type=int(action.action_type),
                                                          polygon_name=action.polygon_name))

    def _publish_polygons(self) -> None:
        """Each enabled zone with ``visualize`` on its ``polygon_pub_topic``, once its shape is known."""
        stamp = self.get_clock().now().to_msg()
        for zone in self.monitor.zones:
            pub = self._polygon_pubs.get(zone.name)
            outline = zone.outline
            if pub is not None and zone.enabled and outline is not None:
                pub.publish(polygon_stamped(self.params.base_frame_id, stamp, outline))

    # -- run-time parameters -----------------------------------------------------------------------
    def _on_enabled(self, parameters: list[Parameter]) -> SetParametersResult:
        """``<polygon>.enabled`` and ``<source>.enabled`` switch a zone or a source on and off."""
        zones = {f"{z.name}.enabled": z for z in self.monitor.zones}
        sources = {f"{s.name}.enabled": s for s in self.sources}
        for param in parameters:
            target = zones.get(param.name) or sources.get(param.name)
            if target is None:
                continue
            if not isinstance(param.value, bool):
                return SetParametersResult(successful=False,
                                           reason=f"{self.get_name()}: {param.name} must be a bool, "
                                                  f"got {param.value!r}")
            target.params = dataclasses.replace(target.params, enabled=param.value)
        return SetParametersResult(successful=True)


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The collision_monitor node, ready to add to an executor."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [CollisionMonitorNode(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.collision.collision_monitor [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role=NODE_NAME)


if __name__ == "__main__":
    raise SystemExit(main())
