"""slam: online grid SLAM on the ROS graph, in the role of slam_toolbox's async mapper and its
localization mode.

Why no worker thread: the outcome must not depend on thread scheduling. A scan is processed on the
executor thread as soon as the odometry at its stamp is in the TF buffer: the scan callback tries at
once, and a scan whose odometry has not arrived yet waits in a one-slot queue and is retried after
every TF message (a newer scan replaces it, as slam_toolbox's async mode drops scans it cannot keep up
with). What is mapped then depends only on the order messages arrive in. A processed scan costs tens
of ms and one with a loop closure a few hundred at most: the map re-render a closure needs goes a
slice of nodes per scan (nav_stack/core/slam/rerender.py), because a callback that held the executor
for seconds starved the bond heartbeat and the lifecycle manager reset the node, losing the map
(turtlebot3_house, 2026-11-27). Meanwhile the executor's other callbacks wait, and under lockstep
(the runner makes this process a ``slam`` participant when ``use_sim_time`` is set) the simulator
waits too, so the map comes out the same however loaded the machine is. Every TIMING_LOG_SCANS
processed scans the node logs the median and max wall time of their callbacks.

  in   ``scan_topic`` (LaserScan, sensor QoS); TF ``odom_frame`` → ``base_frame`` at the scan stamp
       (a scan waits up to SCAN_TF_WAIT s of the node clock for its odometry) and the static
       base → laser pose.
  out  ``map`` (OccupancyGrid, reliable transient local depth 1) after the first scan and then at
       most every ``map_update_interval`` sim s; it grows (size and origin change) as the robot
       explores, and the global costmap's static layer re-sizes to it.
       map → odom on /tf stamped now + ``transform_timeout`` after every scan and re-sent every
       ``transform_publish_period`` s of the node clock (sim s under use_sim_time, so the rate in
       sim time holds at any simulation speed), so TF never goes stale while the robot stands still.
       ``slam/pose`` (PoseWithCovarianceStamped, map frame, scan stamp) for every scan.
  srv  ``slam/save_map``, ``slam/pause_new_measurements`` (SetBool), and slam_toolbox's
       ``slam_toolbox/serialize_map``, ``slam_toolbox/deserialize_map`` and
       ``slam_toolbox/pause_new_measurements`` (Pause, a toggle): see nav_stack/ros/slam/slam_services.py.

Modes (slam_toolbox's ``mode``): ``mapping`` builds the graph, from scratch or, with
``map_file_name`` (a graph written by serialize_map, path without extension), continuing the saved
one with the robot at ``map_start_pose`` (at the graph's first node with ``map_start_at_dock``).
``localization`` needs ``map_file_name``: it matches scans against the saved graph to publish
map → odom, adds nothing to it, and /map stays the saved map (nav_stack/core/slam/localization.py).
A graph that cannot be loaded fails configure, naming the file and field.

Nav2 semantics kept: like slam_toolbox, this node publishes no ``amcl_pose``. A client that waits for
AMCL (BasicNavigator.waitUntilNav2Active) must skip localization in SLAM mode (Nav2's own tutorial
does so with ``localizer='slam'`` semantics); our tools wait for ``bt_navigator`` and ``/map``.
Parameters: every SlamParams field (slam_toolbox names, incl. ``map_start_pose`` [x, y, yaw]) plus
SlamNodeParams (incl. ``mode``, ``map_file_name``, ``map_start_at_dock``), all in the ``slam``
section of config/nav2_params.yaml.
"""

from __future__ import annotations

import math
import sys
import time
from typing import Any

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import OccupancyGrid
from rclpy.time import Time
from sensor_msgs.msg import LaserScan as LaserScanMsg

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D
from nav_stack.core.slam import GridSlam, SlamParams, read_graph, resume
from nav_stack.ros.common.conversions import occupancy_msg, pose_from_2d
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import LATCHED, SENSOR
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from nav_stack.ros.slam.slam_inputs import NotifyingListener, PendingScan, SlamNodeParams
from nav_stack.ros.slam.slam_services import SlamServices
from ros_tools.tf.buffer import ExtrapolationError, TransformError
from ros_tools.tf.ros import TransformBroadcaster, stamp_to_seconds, transform_to_msg
from ros_tools.tf.transform import Transform

NODE_NAME = "slam"
MAP_TOPIC = "map"
POSE_TOPIC = "~/pose"
SCAN_TF_WAIT = 0.3  # s of the node clock a scan may wait for the odometry at its stamp
WARN_PERIOD = 5.0  # s between repeated warnings
TIMING_LOG_SCANS = 100  # processed scans per logged summary of callback times
ACTIVE_MESSAGE = "slam: active, {mode} from scans"


def _time_msg(seconds: float) -> object:
    return Time(nanoseconds=round(seconds * 1e9)).to_msg()


class SlamNode(NavLifecycleNode):
    """The ``slam`` lifecycle node; see the module docstring for its ROS surface.

    Every callback (scans, TF, timer, services) runs on the executor thread, one at a time.
    """

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self.params = SlamParams()
        self.node_params = SlamNodeParams()
        self.slam: GridSlam | None = None
        self.map_msg: OccupancyGrid | None = None
        self.process_times: list[float] = []  # wall s of each processed scan (bench/bench_slam_system.py)
        self.callback_times: list[float] = []  # wall s of each processed scan's whole callback, map included
        self.paused = False
        self.ignored_scans = 0  # scans received while paused, since the last pause
        self.parked_scans = 0  # scans that arrived before their odometry and waited for it
        self.dropped_scans = 0  # scans that never found their odometry (replaced, too old, or timed out)
        self._pending: PendingScan | None = None
        self._laser_poses: dict[str, Pose2D] = {}
        self._map_to_odom: Pose2D | None = None
        self._last_map_stamp = -math.inf
        self._entities: list[object] = []
        self._active: list[object] = []

    # -- lifecycle -----------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = declare_dataclass(self, SlamParams)
        self.node_params = declare_dataclass(self, SlamNodeParams)
        p = self.node_params
        if p.map_file_name:  # a GraphFileError names the file and field and fails configure
            start = None if p.map_start_at_dock else Pose2D(*self.params.map_start_pose)
            self.slam = resume(read_graph(p.map_file_name), self.params, start, p.mode == "localization")
        else:
            self.slam = GridSlam(self.params)
        self.tf = NotifyingListener(self, self._retry_pending)
        self.tf_broadcaster = TransformBroadcaster(self)
        self.map_pub = self.create_publisher(OccupancyGrid, MAP_TOPIC, LATCHED)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, POSE_TOPIC, LATCHED)
        self._entities = [self.map_pub, self.pose_pub, *SlamServices(self).create()]
        if p.map_file_name:
            self.load_session(self.slam, f"slam: loaded {p.map_file_name}, {p.mode}")

    def activate(self) -> None:
        p = self.node_params
        self._active = [self.create_subscription(LaserScanMsg, p.scan_topic, self._on_scan, SENSOR)]
        if p.transform_publish_period > 0.0:
            self._active.append(self.create_timer(p.transform_publish_period, self._send_tf))
        self.get_logger().info(ACTIVE_MESSAGE.format(mode=self.node_params.mode))

    def inputs_heard(self) -> bool:
        """Active, with a matched publisher on the scan topic and another node publishing on /tf.

        Why: the first scan mapped is taken to be at ``map_start_pose``. Lockstep waits for this
        (``main``'s ``ready``) so that the simulator does not drive off while the scan subscription
        is still matching: a CI run mapped its first scan 0.6 m from the start, and the whole tour
        was that far off. A /tf publisher of another node, not any: this node's own map → odom
        broadcaster would count, and a fresh node restarted on a serialized graph in a running world
        then missed a whole leg of odometry. (Not the odometry itself: the simulator publishes none
        before its first step, which waits for this.)
        """
        scan: Any = self._active[0] if self._active else None  # activate() puts the subscription first
        others = [info for info in self.get_publishers_info_by_topic("/tf")
                  if (info.node_name, info.node_namespace) != (self.get_name(), self.get_namespace())]
        return scan is not None and scan.get_publisher_count() > 0 and bool(others)

    def deactivate(self) -> None:
        self._pending = None
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

    def load_session(self, slam: GridSlam, message: str) -> None:
        """Replace the session by a loaded one (GridSlam resuming, or GraphLocalizer) and publish its map.

        map → odom is withheld until the next scan places the robot: the old correction belongs to
        another map (or odom frame) and would be wrong.
        """
        self.slam, self._map_to_odom, self._pending = slam, None, None
        self._last_map_stamp = -math.inf
        self._publish_map(self.get_clock().now().to_msg())
        self.get_logger().info(f"{message}: {len(slam.poses)} nodes")

    # -- scans: processed on arrival, or parked until their odometry arrives ----------------------
    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _on_scan(self, msg: LaserScanMsg) -> None:
        if self.paused:
            self.ignored_scans += 1
            return
        if self._pending is not None:
            self._drop("a newer scan arrived before its odometry")
        self._pending = PendingScan(msg, self._now())
        self._retry_pending()
        if self._pending is not None:
            self.parked_scans += 1

    def _retry_pending(self) -> None:
        """Process the parked scan if its transforms are in the buffer now; drop it if they never will be."""
        pending = self._pending
        if pending is None:
            return
        try:
            transforms = self._transforms(pending.msg)
        except TransformError as error:
            past = isinstance(error, ExtrapolationError) and "past" in str(error)
            if past or self._now() - pending.received > SCAN_TF_WAIT:
                self._drop(f"no transform for a scan: {error}")
            return
        self._pending = None
        if self.paused:
            return
        try:
            self._handle(pending.msg, *transforms)
        except Exception as error:  # a bad scan or a clock jump must not kill mapping
            self.get_logger().warning(f"dropped a scan: {error}", throttle_duration_sec=WARN_PERIOD)

    def _drop(self, reason: str) -> None:
        self._pending = None
        self.dropped_scans += 1
        self.get_logger().warning(reason, throttle_duration_sec=WARN_PERIOD)

    def _transforms(self, msg: LaserScanMsg) -> tuple[Pose2D, Transform]:
        """(laser pose in the base frame, odometry at the scan stamp); raises TransformError."""
        p = self.node_params
        frame = msg.header.frame_id.lstrip("/")
        if frame not in self._laser_poses:
            laser = self.tf.lookup(p.base_frame, frame, None)
            self._laser_poses[frame] = Pose2D(laser.x, laser.y, laser.yaw)
        odom = self.tf.lookup(p.odom_frame, p.base_frame, stamp_to_seconds(msg.header.stamp))
        return self._laser_poses[frame], odom

    def _handle(self, msg: LaserScanMsg, laser: Pose2D, odom: Transform) -> None:
        stamp = stamp_to_seconds(msg.header.stamp)
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        scan = LaserScan(ranges, msg.angle_min, msg.angle_increment, msg.range_min, msg.range_max)
        started = time.perf_counter()
        assert self.slam is not None
        update = self.slam.process(scan, Pose2D(odom.x, odom.y, odom.yaw), stamp, laser)
        if update.processed:
            self.process_times.append(time.perf_counter() - started)
        self._map_to_odom = update.map_to_odom
        self._send_tf()
        self._publish_pose(update.pose, msg.header.stamp)
        if update.processed and stamp - self._last_map_stamp >= self.params.map_update_interval:
            self._last_map_stamp = stamp
            self._publish_map(msg.header.stamp)
        if update.processed:
            self._record_time(time.perf_counter() - started)

    def _record_time(self, seconds: float) -> None:
        """Keep the wall time of a processed scan's callback and log a summary every TIMING_LOG_SCANS.

        Why logged: a callback that holds the executor for seconds starves the bond heartbeat (the
        lifecycle manager resets the node after 4 s) and lockstep; the log shows how close a run came.
        """
        self.callback_times.append(seconds)
        if len(self.callback_times) % TIMING_LOG_SCANS == 0:
            last = np.array(self.callback_times[-TIMING_LOG_SCANS:]) * 1e3
            assert self.slam is not None
            self.get_logger().info(
                f"slam: {len(self.slam.poses)} nodes, last {TIMING_LOG_SCANS} scans: median "
                f"{np.median(last):.0f} ms, max {last.max():.0f} ms wall per scan callback")

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
        assert self.slam is not None
        data, spec = self.slam.occupancy(complete=False)  # a pending re-render goes on a slice per scan
        self.map_msg = occupancy_msg(data, spec, self.node_params.map_frame, stamp)
        self.map_pub.publish(self.map_msg)


def main(argv: list[str] | None = None) -> int:
    """Run the node: ``[--autostart] [--executor events|single] --ros-args --params-file
    config/nav2_params.yaml``. ``--autostart`` configures and activates it (else a lifecycle manager
    does); with ``use_sim_time`` the process takes part in lockstep as ``slam``."""
    from ros_tools.runtime.runner import run_nodes, split_runner_flags

    autostart, executor, rclpy_args = split_runner_flags(sys.argv if argv is None else argv, __doc__)
    nodes: list[SlamNode] = []

    def build() -> list[SlamNode]:
        nodes.append(SlamNode())
        return nodes

    return run_nodes(build, role="slam", rclpy_args=rclpy_args, executor=executor, autostart=autostart,
                     ready=lambda: bool(nodes) and nodes[0].inputs_heard())


if __name__ == "__main__":
    sys.exit(main())
