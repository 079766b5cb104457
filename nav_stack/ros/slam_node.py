"""slam: online grid SLAM on the ROS graph, in the role of slam_toolbox's async mapper.

Why a worker thread: a processed scan costs tens of ms and a loop closure (graph solve and map
rebuild) up to seconds; done in a callback it would stall TF, /clock and the services. The scan
callback only parks the newest scan in a one-slot mailbox (older unprocessed ones are dropped, as
slam_toolbox's async mode does), and the worker looks up odometry, runs the core
(``nav_stack.core.slam.GridSlam``) and publishes.

  in   ``scan_topic`` (LaserScan, sensor QoS); TF ``odom_frame`` → ``base_frame`` at the scan stamp
       (a scan waits up to SCAN_TF_WAIT wall s for its odometry) and the static base → laser pose.
  out  ``map`` (OccupancyGrid, reliable transient local depth 1) after the first scan and then at
       most every ``map_update_interval`` sim s; it grows (size and origin change) as the robot
       explores, and the global costmap's static layer re-sizes to it.
       map → odom on /tf stamped now + ``transform_timeout`` after every scan and re-sent every
       ``transform_publish_period`` wall s, so TF never goes stale while the robot stands still.
       ``slam/pose`` (PoseWithCovarianceStamped, map frame, scan stamp) for every scan.
  srv  ``slam/save_map`` (nav2_msgs/SaveMap semantics: ``map_url`` is the path without extension,
       thresholds 0 mean SAVE_FREE_THRESH / SAVE_OCCUPIED_THRESH; only pgm / trinary are written) and
       ``slam/pause_new_measurements`` (std_srvs/SetBool; true ignores scans, map and TF stay).

Nav2 semantics kept: like slam_toolbox, this node publishes no ``amcl_pose``. A client that waits for
AMCL (BasicNavigator.waitUntilNav2Active) must skip localization in SLAM mode (Nav2's own tutorial
does so with ``localizer='slam'`` semantics); our tools wait for ``bt_navigator`` and ``/map``.
Parameters: every SlamParams field (slam_toolbox names, incl. ``map_start_pose`` [x, y, yaw]) plus
SlamNodeParams, all in the ``slam`` section of config/nav2_params.yaml.
"""

from __future__ import annotations

import math
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.clock import Clock, ClockType
from rclpy.time import Time
from sensor_msgs.msg import LaserScan as LaserScanMsg
from std_srvs.srv import SetBool

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D
from nav_stack.core.map_io import OccupancyMap, save_map
from nav_stack.core.slam import GridSlam, SlamParams
from nav_stack.ros.conversions import occupancy_msg, pose_from_2d
from nav_stack.ros.lifecycle import NavLifecycleNode
from nav_stack.ros.params import declare_dataclass
from nav_stack.ros.qos import LATCHED, SENSOR
from ros_tools.tf.buffer import ExtrapolationError, TransformError
from ros_tools.tf.ros import TransformBroadcaster, TransformListener, stamp_to_seconds, transform_to_msg
from ros_tools.tf.transform import Transform

NODE_NAME = "slam"
MAP_TOPIC = "map"
POSE_TOPIC = "~/pose"
SAVE_MAP_SERVICE = "~/save_map"
PAUSE_SERVICE = "~/pause_new_measurements"
SCAN_TF_WAIT = 0.3  # wall s a scan may wait for the odometry at its stamp
TF_POLL = 0.005  # wall s between TF polls while waiting
WARN_PERIOD = 5.0  # s between repeated warnings
ACTIVE_MESSAGE = "slam: active, mapping from scans"
# Thresholds written by save_map when the request leaves them 0. Not Nav2 map_saver's 0.25: with it the
# unknown pixel 205 (occ = 50/255 = 0.196) reloads as *free* (slam_toolbox issue #587); ROS 1's 0.196
# keeps it unknown.
SAVE_FREE_THRESH = 0.196
SAVE_OCCUPIED_THRESH = 0.65


@dataclass(frozen=True)
class SlamNodeParams:
    """ROS-side knobs, slam_toolbox names (frames, topic) and defaults unless noted.

    Attributes:
        odom_frame / map_frame / base_frame: TF frames (base_footprint: the frame sim2d's odometry moves).
        scan_topic: LaserScan topic.
        transform_timeout: map → odom is stamped this far (s) into the future, AMCL's transform_tolerance.
        transform_publish_period: wall period (s) of the map → odom re-publication (0 disables it).
    """

    odom_frame: str = "odom"
    map_frame: str = "map"
    base_frame: str = "base_footprint"
    scan_topic: str = "/scan"
    transform_timeout: float = 0.2
    transform_publish_period: float = 0.05

    def __post_init__(self) -> None:
        for name in ("transform_timeout", "transform_publish_period"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"SlamNodeParams.{name} must be a finite number >= 0, got {value}")


def _time_msg(seconds: float) -> object:
    return Time(nanoseconds=round(seconds * 1e9)).to_msg()


class SlamNode(NavLifecycleNode):
    """The ``slam`` lifecycle node; see the module docstring for its ROS surface."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self.params = SlamParams()
        self.node_params = SlamNodeParams()
        self.slam: GridSlam | None = None
        self.map_msg: OccupancyGrid | None = None
        self.process_times: list[float] = []  # wall s of each processed scan (bench/bench_slam_system.py)
        self.paused = False
        self.ignored_scans = 0  # scans received while paused, since the last pause
        self._slam_lock = threading.Lock()
        self._mailbox = threading.Condition()
        self._latest: tuple[LaserScanMsg, float] | None = None
        self._stop = False
        self._worker: threading.Thread | None = None
        self._laser_poses: dict[str, Pose2D] = {}
        self._map_to_odom: Pose2D | None = None
        self._last_map_stamp = -math.inf
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._entities: list[object] = []
        self._active: list[object] = []

    # -- lifecycle -----------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = declare_dataclass(self, SlamParams)
        self.node_params = declare_dataclass(self, SlamNodeParams)
        self.slam = GridSlam(self.params)
        self.tf = TransformListener(self)
        self.tf_broadcaster = TransformBroadcaster(self)
        self.map_pub = self.create_publisher(OccupancyGrid, MAP_TOPIC, LATCHED)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, POSE_TOPIC, LATCHED)
        services = MutuallyExclusiveCallbackGroup()
        self._entities = [
            self.map_pub, self.pose_pub,
            self.create_service(SaveMap, SAVE_MAP_SERVICE, self._on_save_map, callback_group=services),
            self.create_service(SetBool, PAUSE_SERVICE, self._on_pause, callback_group=services),
        ]

    def activate(self) -> None:
        p = self.node_params
        self._active = [self.create_subscription(LaserScanMsg, p.scan_topic, self._on_scan, SENSOR)]
        if p.transform_publish_period > 0.0:
            timer = self.create_timer(p.transform_publish_period, self._send_tf, clock=self._steady)
            self._active.append(timer)
        self._stop = False
        self._worker = threading.Thread(target=self._work, name="slam_worker", daemon=True)
        self._worker.start()
        self.get_logger().info(ACTIVE_MESSAGE)

    def deactivate(self) -> None:
        with self._mailbox:
            self._stop = True
            self._latest = None
            self._mailbox.notify_all()
        if self._worker is not None:
            self._worker.join(timeout=10.0)
            self._worker = None
        for entity in self._active:
            self._destroy(entity)
        self._active = []

    def cleanup(self) -> None:
        for entity in self._entities:
            self._destroy(entity)
        self._entities = []
        self.tf.destroy()
        self.slam, self.map_msg, self._map_to_odom = None, None, None
        self._laser_poses.clear()
        self._last_map_stamp = -math.inf

    def destroy_node(self) -> None:
        self.deactivate()
        super().destroy_node()

    def _destroy(self, entity: object) -> None:
        getattr(self, f"destroy_{type(entity).__name__.lower()}")(entity)

    # -- scans: the callback parks, the worker processes ----------------------------------------
    def _on_scan(self, msg: LaserScanMsg) -> None:
        if self.paused:
            self.ignored_scans += 1
            return
        with self._mailbox:
            self._latest = (msg, time.monotonic())
            self._mailbox.notify()

    def _work(self) -> None:
        while True:
            with self._mailbox:
                self._mailbox.wait_for(lambda: self._stop or self._latest is not None)
                if self._stop:
                    return
                assert self._latest is not None
                msg, received = self._latest
                self._latest = None
            try:
                self._handle(msg, received)
            except Exception as error:  # a bad scan or a clock jump must not kill mapping
                self.get_logger().warning(f"dropped a scan: {error}", throttle_duration_sec=WARN_PERIOD)

    def _wait_for(self, target: str, source: str, stamp: float | None, received: float) -> Transform | None:
        """TF ``target`` ← ``source`` at ``stamp``, polled until SCAN_TF_WAIT after ``received``."""
        while True:
            try:
                return self.tf.lookup(target, source, stamp)
            except TransformError as error:
                past = isinstance(error, ExtrapolationError) and "past" in str(error)
                if past or self._stop or time.monotonic() - received > SCAN_TF_WAIT:
                    self.get_logger().warning(f"no transform for a scan: {error}",
                                              throttle_duration_sec=WARN_PERIOD)
                    return None
            time.sleep(TF_POLL)  # the worker thread, never an executor callback

    def _handle(self, msg: LaserScanMsg, received: float) -> None:
        p = self.node_params
        frame = msg.header.frame_id.lstrip("/")
        if frame not in self._laser_poses:
            laser = self._wait_for(p.base_frame, frame, None, received)
            if laser is None:
                return
            self._laser_poses[frame] = Pose2D(laser.x, laser.y, laser.yaw)
        stamp = stamp_to_seconds(msg.header.stamp)
        odom = self._wait_for(p.odom_frame, p.base_frame, stamp, received)
        if odom is None or self.paused:
            return
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        scan = LaserScan(ranges, msg.angle_min, msg.angle_increment, msg.range_min, msg.range_max)
        started = time.perf_counter()
        with self._slam_lock:
            assert self.slam is not None
            odom_pose = Pose2D(odom.x, odom.y, odom.yaw)
            update = self.slam.process(scan, odom_pose, stamp, self._laser_poses[frame])
        if update.processed:
            self.process_times.append(time.perf_counter() - started)
        self._map_to_odom = update.map_to_odom
        self._send_tf()
        self._publish_pose(update.pose, msg.header.stamp)
        if update.processed and stamp - self._last_map_stamp >= self.params.map_update_interval:
            self._last_map_stamp = stamp
            self._publish_map(msg.header.stamp)

    # -- outputs ---------------------------------------------------------------------------------
    def _send_tf(self) -> None:
        correction = self._map_to_odom
        if correction is None:
            return
        p = self.node_params
        stamp = self.get_clock().now().nanoseconds * 1e-9 + p.transform_timeout
        transform = Transform.from_xy_yaw(*correction)
        self.tf_broadcaster.send([transform_to_msg(transform, p.map_frame, p.odom_frame, _time_msg(stamp))])

    def _publish_pose(self, pose: Pose2D, stamp: object) -> None:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id, msg.header.stamp = self.node_params.map_frame, stamp
        msg.pose.pose = pose_from_2d(*pose)
        covariance = [0.0] * 36
        covariance[0] = covariance[7] = self.params.link_stddev_xy**2
        covariance[35] = self.params.link_stddev_yaw**2
        msg.pose.covariance = covariance
        self.pose_pub.publish(msg)

    def _publish_map(self, stamp: object) -> None:
        with self._slam_lock:
            assert self.slam is not None
            data, spec = self.slam.occupancy()
        self.map_msg = occupancy_msg(data, spec, self.node_params.map_frame, stamp)
        self.map_pub.publish(self.map_msg)

    # -- services --------------------------------------------------------------------------------
    def _on_pause(self, request: SetBool.Request, response: SetBool.Response) -> SetBool.Response:
        if request.data and not self.paused:
            self.ignored_scans = 0
        elif not request.data and self.paused:
            self.get_logger().info(f"ignored {self.ignored_scans} scans while paused")
        self.paused = bool(request.data)
        response.success = True
        response.message = "new measurements paused" if self.paused else "new measurements resumed"
        self.get_logger().info(response.message)
        return response

    def _on_save_map(self, request: SaveMap.Request, response: SaveMap.Response) -> SaveMap.Response:
        response.result = False
        image_format = request.image_format.lower() or "pgm"
        mode = request.map_mode.lower() or "trinary"
        if image_format != "pgm" or mode != "trinary":
            self.get_logger().error(f"save_map: only pgm / trinary maps are written, got image_format="
                                    f"{request.image_format!r}, map_mode={request.map_mode!r}")
            return response
        free = request.free_thresh or SAVE_FREE_THRESH
        occupied = request.occupied_thresh or SAVE_OCCUPIED_THRESH
        with self._slam_lock:
            if self.slam is None or not self.slam.poses.size:
                self.get_logger().error("save_map: no map yet (no scan processed)")
                return response
            data, spec = self.slam.occupancy()
        base = Path(request.map_url or "map").expanduser()
        try:
            yaml_path, _ = save_map(OccupancyMap(data, spec), base, free_thresh=free,
                                    occupied_thresh=occupied, overwrite=True)
        except (OSError, ValueError) as error:
            self.get_logger().error(f"save_map: cannot write {base}: {error}")
            return response
        self.get_logger().info(f"save_map: wrote {yaml_path} ({spec.width} x {spec.height} cells)")
        response.result = True
        return response


def main(argv: list[str] | None = None) -> int:
    """Run the node (``--ros-args --params-file config/nav2_params.yaml``; ``--autostart`` brings it up)."""
    from nav_stack.ros.node_runner import run

    return run(lambda: [SlamNode()], argv)


if __name__ == "__main__":
    sys.exit(main())
