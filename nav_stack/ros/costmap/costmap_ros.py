"""CostmapROS: a lifecycle node hosting a core LayeredCostmap, like nav2_costmap_2d::Costmap2DROS.

Nav2 runs a costmap as its own lifecycle node inside the server that uses it: planner_server owns
``global_costmap`` (namespace ``global_costmap``), controller_server owns ``local_costmap``. The
owner drives this node's transitions from its own and reads the costs directly through
:meth:`snapshot` (a copy, so a plan or a control cycle works on one consistent grid) and awaits
:attr:`ready` (a future done at the first successful update) before its first plan.

Data in: the map (``<static>.map_topic``, transient local), laser scans (``<obstacle>.<source>.topic``,
sensor QoS), the robot pose from TF. A scan is added with the sensor pose at its stamp; when TF has
not caught up with the stamp yet the scan waits (at most ``transform_tolerance`` + 1 s of the node clock,
sim s under use_sim_time, so a busy machine never drops it) and is retried each cycle. Readings
follow REP 117: -inf (closer than range_min) and NaN are dropped, +inf ("no return") clears up to
the raytrace range when ``inf_is_valid`` (our yaml enables it).

Out, at ``publish_frequency``, as Nav2's Costmap2DPublisher (nav_stack.ros.costmap.costmap_publisher): the
full ``costmap`` (OccupancyGrid) and ``costmap_raw`` (nav2_msgs/Costmap) on activation, to a new subscriber,
on resize or a rolling window's move (every cycle with ``always_send_full_costmap``), otherwise
``costmap_updates`` / ``costmap_raw_updates`` with the redrawn window only, each only when subscribed;
``published_footprint`` (PolygonStamped); all reliable transient local depth 1; services
``clear_entirely_<name>`` and ``get_costmap``. ``<layer>.enabled`` may be set at run time (Nav2's
dynamic parameters; SMACC2's CpCostmapSwitch does): the layer stops or resumes contributing and the
whole grid is redrawn at the next update. Relative topic names resolve against the owner's
namespace (Nav2's joinWithParentNamespace), so ``map`` is ``/map``.
"""

from __future__ import annotations

import threading
from collections import deque

import numpy as np
from geometry_msgs.msg import Point32, PolygonStamped
from nav2_msgs.srv import ClearEntireCostmap, GetCostmap
from nav_msgs.msg import OccupancyGrid
from rcl_interfaces.msg import SetParametersResult
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from rclpy.task import Future
from rclpy.timer import Timer
from sensor_msgs.msg import LaserScan as LaserScanMsg

from nav_stack.core.costmap import (
    CostmapParams,
    LaserScan,
    LayeredCostmap,
    ObstacleLayer,
    StaticLayer,
)
from nav_stack.core.grid import GridSpec
from nav_stack.ros.common.conversions import costmap_msg, grid_from_occupancy
from nav_stack.ros.common.frames import FrameError, Frames, pose_of
from nav_stack.ros.common.qos import DEFAULT, LATCHED, SENSOR
from nav_stack.ros.costmap.costmap_params import build_layers, declare_costmap_params
from nav_stack.ros.costmap.costmap_publisher import CostmapPublisher
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.runtime.timers import create_periodic_timer
from ros_tools.tf import TransformError
from ros_tools.tf.ros import stamp_to_seconds

SCAN_WAIT_SLACK = 1.0  # s of the node clock a scan may wait for TF beyond transform_tolerance
FIRST_UPDATE_RETRY = 0.1  # s between attempts at the first update, when update_frequency is slower


def run_transition(node: LifecycleNode, transition: str) -> None:
    """Drive an owned node through ``configure``/``activate``/``deactivate``/``cleanup``; raise on failure."""
    outcome = getattr(node, f"trigger_{transition}")()
    if outcome != TransitionCallbackReturn.SUCCESS:
        raise RuntimeError(f"{node.get_name()}: {transition} failed (see its log)")


class CostmapROS(NavLifecycleNode):
    """``global_costmap`` / ``local_costmap`` node; call :meth:`snapshot` from any thread."""

    def __init__(self, name: str = "global_costmap", namespace: str | None = None,
                 parent_namespace: str = "/", defaults: CostmapParams | None = None,
                 **kwargs: object) -> None:
        super().__init__(name, namespace=namespace if namespace is not None else name, **kwargs)
        self._defaults = defaults or (CostmapParams.local_defaults() if name == "local_costmap"
                                      else CostmapParams())
        self._parent_ns = parent_namespace.rstrip("/")
        self._lock = threading.Lock()
        self.params = self._defaults
        self.costmap: LayeredCostmap | None = None
        self.frames: Frames | None = None
        self._pending_scans: deque[tuple[LaserScanMsg, float]] = deque(maxlen=50)
        self.ready = Future()  # done at the first successful update
        self._map_received = False
        self._entities: list[object] = []
        self._layer_timers: list[object] = []
        self._warmup_timer: Timer | None = None
        self._cleared = False  # cleared entirely, and no update with a scan since
        self._scan_since_clear = False

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = declare_costmap_params(self, self._defaults)
        self.costmap = LayeredCostmap(self.params, build_layers(self, self.params))
        self.frames = Frames(self, self.params.robot_base_frame)
        self._grid_publisher = CostmapPublisher(self, self.global_frame, self.params.always_send_full_costmap)
        self._pub_footprint = self.create_publisher(PolygonStamped, "published_footprint", LATCHED)
        self._entities = [*self._grid_publisher.publishers, self._pub_footprint]
        for layer in self.costmap.layers:
            if isinstance(layer, StaticLayer):
                qos = LATCHED if layer.params.map_subscribe_transient_local else DEFAULT
                self._entities.append(self.create_subscription(
                    OccupancyGrid, self._topic(layer.params.map_topic), self._on_map, qos))
            elif isinstance(layer, ObstacleLayer):
                depth50 = QoSProfile(depth=50, reliability=SENSOR.reliability, durability=SENSOR.durability)
                self._entities.append(self.create_subscription(
                    LaserScanMsg, self._topic(layer.params.topic), self._on_scan, depth50))
        self.add_on_set_parameters_callback(self._on_layer_switch)
        name = self.get_name()
        self._entities += [
            self.create_service(ClearEntireCostmap, f"clear_entirely_{name}", self._on_clear),
            self.create_service(GetCostmap, "get_costmap", self._on_get_costmap),
        ]

    def _on_layer_switch(self, parameters: list[Parameter]) -> SetParametersResult:
        """Apply ``<layer>.enabled`` changes; a non-boolean value is refused, naming it."""
        layers = {layer.name: layer for layer in self.costmap.layers} if self.costmap is not None else {}
        for parameter in parameters:
            layer_name, _, field = parameter.name.rpartition(".")
            if field != "enabled" or layer_name not in layers:
                continue
            if not isinstance(parameter.value, bool):
                return SetParametersResult(successful=False, reason=(
                    f"{self.get_name()}: {parameter.name} must be a bool, got {parameter.value!r}"))
            with self._lock:
                layers[layer_name].enabled = parameter.value
                self.costmap.redraw_all()  # type: ignore[union-attr]
            self.get_logger().info(f"layer '{layer_name}' {'enabled' if parameter.value else 'disabled'}")
        return SetParametersResult(successful=True)

    def activate(self) -> None:
        p = self.params
        self._grid_publisher.reset()  # the full grid first, as at every activation
        self._layer_timers = [
            create_periodic_timer(self, 1.0 / p.update_frequency, self._update),
            create_periodic_timer(self, 1.0 / p.publish_frequency, self._publish),
        ]
        if p.update_frequency < 1.0 / FIRST_UPDATE_RETRY:
            self._warmup_timer = self.create_timer(FIRST_UPDATE_RETRY, self._update_until_ready)
            self._layer_timers.append(self._warmup_timer)

    def _update_until_ready(self) -> None:
        """Retry the first update every FIRST_UPDATE_RETRY s until it succeeds, then stop.

        Why: the global costmap updates at 1 Hz, and its first update needs both the map and the robot
        pose (AMCL's map -> odom). A plan requested right after localization then waited up to a
        second more for it, beyond the planner's costmap_update_timeout (1 s) under load: TIMEOUT.
        """
        if not self.ready.done():
            self._update()
        if self.ready.done() and self._warmup_timer is not None:  # None: first tick before assignment
            self._warmup_timer.cancel()

    def deactivate(self) -> None:
        for timer in self._layer_timers:
            self.destroy_timer(timer)  # type: ignore[arg-type]
        self._layer_timers = []
        self._warmup_timer = None

    def cleanup(self) -> None:
        self.deactivate()
        for entity in self._entities:
            for destroy in (self.destroy_publisher, self.destroy_subscription, self.destroy_service):
                if destroy(entity):  # type: ignore[arg-type]
                    break
        self._entities = []
        if self.frames is not None:
            self.frames.destroy()
        self.frames, self.costmap = None, None
        self.ready = Future()

    # -- what owners use -------------------------------------------------------------------------
    @property
    def global_frame(self) -> str:
        return self.params.global_frame

    def snapshot(self) -> tuple[np.ndarray, GridSpec] | None:
        """A copy of the current costs and their grid, or None before the first update."""
        with self._lock:
            if self.costmap is None or not self.costmap.is_sized or not self.ready.done():
                return None
            return self.costmap.costs.copy(), self.costmap.spec


    # -- callbacks --------------------------------------------------------------------------------
    def _topic(self, name: str) -> str:
        return name if name.startswith("/") else f"{self._parent_ns}/{name}"

    def _on_map(self, msg: OccupancyGrid) -> None:
        data, spec = grid_from_occupancy(msg)
        with self._lock:
            assert self.costmap is not None
            self.costmap.set_map(data, spec)
        self._map_received = True
        self.get_logger().info(f"received a {spec.width} x {spec.height} map at {spec.resolution} m/cell")

    @property
    def has_map(self) -> bool:
        """True once the static layer has its map (always, for a costmap without a static layer).

        Why: in lockstep the process holds the simulator until this is true. A map from another
        process arrives after DDS discovery, which takes wall seconds under load; at a high real-time
        factor the planner's costmap_update_timeout (sim s) would otherwise run out before it.
        """
        return self._map_received or self.costmap is None or not any(
            isinstance(layer, StaticLayer) for layer in self.costmap.layers)

    @property
    def current(self) -> bool:
        """False from a clear_entirely until an update has drawn a scan received after it.

        Why: cleared, the obstacle layer is empty until an update draws the next scan (the first scan
        after a clear is drawn at once). A controller checking its commands against that empty grid
        drove at full speed into a pillar the recovery had just cleared away (the battery patrol, CI).
        Nav2's controller likewise waits while its costmap is not current.
        """
        return not self._cleared

    def _on_scan(self, msg: LaserScanMsg) -> None:
        self._pending_scans.append((msg, self.get_clock().now().nanoseconds * 1e-9))
        self._add_scans()
        if self._cleared and self._scan_since_clear:
            self._update()  # current again with the first scan, not at the next timer tick

    def _add_scans(self) -> None:
        """Give the obstacle layers every waiting scan whose sensor pose TF can now tell."""
        assert self.frames is not None and self.costmap is not None
        keep: deque[tuple[LaserScanMsg, float]] = deque(maxlen=50)
        now = self.get_clock().now().nanoseconds * 1e-9
        while self._pending_scans:
            msg, received = self._pending_scans.popleft()
            try:
                tf = self.frames.listener.lookup(self.global_frame, msg.header.frame_id,
                                                 stamp_to_seconds(msg.header.stamp))
            except TransformError:
                if now - received < self.params.transform_tolerance + SCAN_WAIT_SLACK:
                    keep.append((msg, received))
                continue
            try:
                scan = LaserScan(np.asarray(msg.ranges, dtype=np.float64), msg.angle_min, msg.angle_increment,
                                 msg.range_min, msg.range_max)
            except ValueError as error:
                self.get_logger().warn(f"dropping a malformed scan: {error}", throttle_duration_sec=5.0)
                continue
            with self._lock:
                for layer in self.costmap.layers:
                    if isinstance(layer, ObstacleLayer):
                        layer.add_scan(scan, pose_of(tf))
                        self._scan_since_clear = True
        self._pending_scans = keep

    def _update(self) -> None:
        assert self.frames is not None and self.costmap is not None
        self._add_scans()
        try:
            pose = self.frames.robot_pose(self.global_frame)
        except FrameError as error:
            self.get_logger().warn(f"costmap not updated: {error}", throttle_duration_sec=5.0)
            return
        with self._lock:
            if not self.costmap.is_sized:
                self.get_logger().info("waiting for the map", throttle_duration_sec=5.0)
                return
            self._grid_publisher.add_window(self.costmap.update(pose))
            if self._scan_since_clear:
                self._cleared = False
        if not self.ready.done():
            self.ready.set_result(True)

    def _publish(self) -> None:
        """Send the grid (whole or the redrawn window, see CostmapPublisher) and the footprint."""
        if self.costmap is None or self.frames is None:
            return
        with self._lock:
            if not self.costmap.is_sized or not self.ready.done():
                return
            messages = self._grid_publisher.prepare(self.costmap.costs, self.costmap.spec)
        self._grid_publisher.send(messages)
        stamp = self.get_clock().now().to_msg()
        try:
            pose = self.frames.robot_pose(self.global_frame)
        except FrameError:
            return
        footprint = PolygonStamped()
        footprint.header.frame_id, footprint.header.stamp = self.global_frame, stamp
        points = self.costmap.footprint.transformed(*pose)
        footprint.polygon.points = [Point32(x=float(x), y=float(y), z=0.0) for x, y in points]
        self._pub_footprint.publish(footprint)

    def _on_clear(self, request: ClearEntireCostmap.Request, response: ClearEntireCostmap.Response
                  ) -> ClearEntireCostmap.Response:
        with self._lock:
            if self.costmap is not None:
                self.costmap.clear_entirely()
                self._cleared = any(isinstance(layer, ObstacleLayer) for layer in self.costmap.layers)
                self._scan_since_clear = False
        self._pending_scans.clear()
        self._update()
        self.get_logger().info("costmap cleared entirely")
        return response

    def _on_get_costmap(self, request: GetCostmap.Request, response: GetCostmap.Response
                        ) -> GetCostmap.Response:
        snap = self.snapshot()
        if snap is not None:
            response.map = costmap_msg(snap[0], snap[1], self.global_frame, self.get_clock().now().to_msg())
        return response
