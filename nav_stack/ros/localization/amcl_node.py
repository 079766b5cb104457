"""amcl: the nav2_amcl lifecycle node around the numpy particle filter of nav_stack.core.localization.

Why: Nav2 clients expect AMCL's exact surface (names, QoS, post-dated map→odom, services); the
filter itself lives in the core, so this node only translates and schedules:

  in   ``map`` (OccupancyGrid, transient local): builds the filter (a new map keeps the last estimate)
       ``scan`` (LaserScan, best effort, depth 1) with TF odom→base_footprint interpolated at the
       scan stamp, never the latest odometry: a scan taken with the robot elsewhere than the
       odometry says moves every particle by the difference. A scan whose stamp is newer than the
       odometry in the buffer waits up to SCAN_TF_WAIT (like Nav2's message filter) and is dropped
       if its odometry does not come. Only the newest scan counts: depth 1 lets the middleware drop
       scans a busy node could not take, a newer scan replaces one still waiting, and a scan not
       newer than the last one used is ignored, so a lagging node never works through a backlog.
       The base→laser offset comes from TF (static). REP 117: +inf (no return) counts as a
       max-range reading, -inf (too close) as below range_min.
       ``initialpose`` (PoseWithCovarianceStamped, reliable depth 10) and the service
       ``set_initial_pose``: rejected with a logged reason when NaN, not in ``global_frame_id`` or
       outside the map; one that arrives before the map (like a global localization request) is
       applied when the map comes.
  out  ``amcl_pose`` (reliable, transient local, depth 1) after each filter update and initial pose;
       ``particle_cloud`` (nav2_msgs/ParticleCloud, best effort, only built when someone listens);
       map→odom on /tf stamped scan time + ``transform_tolerance``; while no scan arrives it is
       re-sent every TF_REPUBLISH_PERIOD at now + transform_tolerance, so TF never goes stale.
       Localization health (not in Nav2, see amcl_health.py): after each filter update, status
       ``amcl: localization`` on /diagnostics and one warning ``localization degraded: <cause>``
       when the estimate stops being trustworthy (few beams on walls, scan off the map, spread cloud).
  srv  ``reinitialize_global_localization`` and ``request_nomotion_update`` (std_srvs/Empty),
       ``set_initial_pose`` (nav2_msgs/SetInitialPose).

Parameters: every nav2_amcl name and Jazzy default (AmclParams); Nav2's nested ``initial_pose.x``,
``.y``, ``.z``, ``.yaw`` are read too and win over the flat ``initial_pose_x``... when set. One
addition, ``random_seed`` (int, default 0): the particle filter's random generator is seeded with it,
so a lockstep run repeats exactly (nav2_amcl seeds with the wall time; -1 does the same here). It is
seeded again at every initial pose, so the cloud drawn there does not depend on how many scans the
filter happened to take before the pose arrived (a matter of DDS timing); and
the health check's thresholds ``health.*`` (HealthParams).
"""

from __future__ import annotations

import math

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.msg import ParticleCloud
from nav2_msgs.srv import SetInitialPose
from nav_msgs.msg import OccupancyGrid
from rclpy.clock import Clock, ClockType
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan as LaserScanMsg
from std_srvs.srv import Empty

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D
from nav_stack.core.localization import Amcl, AmclParams, PoseEstimate, map_to_odom
from nav_stack.core.localization.params import LIKELIHOOD_FIELD_PROB
from nav_stack.ros.common.conversions import grid_from_occupancy, pose_to_2d
from nav_stack.ros.common.frames import pose_of
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.qos import DEFAULT, LATCHED, PARTICLE_CLOUD
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from nav_stack.ros.localization.amcl_health import HealthReport
from nav_stack.ros.localization.amcl_messages import (
    covariance_3x3,
    estimate_msg,
    particle_cloud_msg,
    time_msg,
)
from nav_stack.ros.localization.amcl_params import DEFAULT_SEED, load_health_params, load_params, random_seed
from ros_tools.tf.buffer import ExtrapolationError, TransformError
from ros_tools.tf.ros import TransformBroadcaster, TransformListener, stamp_to_seconds, transform_to_msg
from ros_tools.tf.transform import Transform

NODE_NAME = "amcl"
#: s of the node clock (sim s under use_sim_time) a scan may wait for odometry at its stamp. Node time,
#: not wall time: under lockstep the simulator cannot run on while this process lags, so a scan is
#: dropped only when its odometry truly never came, never because the machine was busy.
SCAN_TF_WAIT = 1.0
PENDING_POLL_PERIOD = 0.01  # wall s
TF_REPUBLISH_PERIOD = 0.1  # wall s
WARN_PERIOD = 2.0  # s between repeated warnings, as Nav2
NO_POSE_WARNING = "AMCL cannot publish a pose or update the transform. Please set the initial pose..."
#: Scans: sensor-data QoS but only the newest sample is kept (see the module docstring).
SCAN_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT, history=HistoryPolicy.KEEP_LAST)


class AmclNode(NavLifecycleNode):
    """Adaptive Monte Carlo Localization node (``amcl``)."""

    def __init__(self, rng: np.random.Generator | None = None, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self._given_rng = rng
        self.rng = rng if rng is not None else np.random.default_rng(DEFAULT_SEED)
        self._seed: int | None = None  # random_seed, re-applied at each initial pose (None: don't)
        self.params = AmclParams()
        self.amcl: Amcl | None = None
        self._pending_pose: tuple[Pose2D, np.ndarray | None, str] | None = None
        self._pending_global = False
        self._pending_scan: tuple[LaserScanMsg, float] | None = None
        self._laser_poses: dict[str, Pose2D] = {}
        self._map_to_odom: Pose2D | None = None
        self._last_tf_stamp = -math.inf
        self._last_scan_stamp = -math.inf
        self._steady_clock = Clock(clock_type=ClockType.STEADY_TIME)
        self._owned: list[object] = []
        self._active_owned: list[object] = []
        self.health: HealthReport | None = None

    # -- lifecycle -----------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = load_params(self)
        self.health_params = load_health_params(self)
        if self.params.do_beamskip and self.params.laser_model_type != LIKELIHOOD_FIELD_PROB:
            # Nav2 skips beams only in its likelihood_field_prob model; with likelihood_field or beam,
            # Nav2 too reads do_beamskip nowhere, silently.
            self.get_logger().warning(
                f"do_beamskip is true but has no effect with laser_model_type "
                f"'{self.params.laser_model_type}': beam skipping only works with laser_model_type "
                f"'{LIKELIHOOD_FIELD_PROB}' (as in Nav2); beam_skip_distance, beam_skip_threshold and "
                "beam_skip_error_threshold are ignored")
        self._seed = None if self._given_rng else random_seed(self)
        self.rng = self._given_rng or np.random.default_rng(self._seed)
        self.tf = TransformListener(self)
        self.tf_broadcaster = TransformBroadcaster(self)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "amcl_pose", LATCHED)
        self.cloud_pub = self.create_publisher(ParticleCloud, "particle_cloud", PARTICLE_CLOUD)
        self._owned = [
            self.pose_pub, self.cloud_pub,
            self.create_service(Empty, "reinitialize_global_localization", self._on_global_localization),
            self.create_service(Empty, "request_nomotion_update", self._on_nomotion_update),
            self.create_service(SetInitialPose, "set_initial_pose", self._on_set_initial_pose),
        ]

    def activate(self) -> None:
        p = self.params
        self._pending_timer = self.create_timer(PENDING_POLL_PERIOD, self._process_pending_scan,
                                                clock=self._steady_clock)
        self._pending_timer.cancel()  # runs only while a scan waits for its odometry
        self._active_owned = [
            self.create_subscription(OccupancyGrid, p.map_topic, self._on_map, LATCHED),
            self.create_subscription(LaserScanMsg, p.scan_topic, self._on_scan, SCAN_QOS),
            self.create_subscription(PoseWithCovarianceStamped, "initialpose", self._on_initial_pose,
                                     DEFAULT),
            self._pending_timer,
            self.create_timer(TF_REPUBLISH_PERIOD, self._republish_tf, clock=self._steady_clock),
        ]
        self.health = HealthReport(self, self.health_params)
        if p.set_initial_pose:
            self._initial_pose(Pose2D(p.initial_pose_x, p.initial_pose_y, p.initial_pose_yaw), None,
                               "parameters")

    def deactivate(self) -> None:
        for entity in self._active_owned:
            self._destroy(entity)
        self._active_owned = []
        if self.health is not None:
            self.health.destroy()
            self.health = None
        self._pending_scan = None
        self._last_scan_stamp = -math.inf

    def cleanup(self) -> None:
        for entity in self._owned:
            self._destroy(entity)
        self._owned = []
        self.tf.destroy()
        self.amcl = None
        self._map_to_odom = None
        self._laser_poses.clear()

    def _destroy(self, entity: object) -> None:
        kind = type(entity).__name__.lower()
        getattr(self, f"destroy_{kind}")(entity)

    # -- map and initial pose --------------------------------------------------------------------
    def _on_map(self, msg: OccupancyGrid) -> None:
        p = self.params
        if p.first_map_only and self.amcl is not None:
            return
        if msg.header.frame_id.lstrip("/") != p.global_frame_id:
            self.get_logger().warning(f"Frame_id of map received:'{msg.header.frame_id}' doesn't match "
                                      f"global_frame_id:'{p.global_frame_id}'")
        data, spec = grid_from_occupancy(msg)
        previous = self.amcl.estimate() if self.amcl is not None and self.amcl.initialized else None
        self.amcl = Amcl(p, data, spec, self.rng)
        self.get_logger().info(f"Received a {spec.width} X {spec.height} map @ {spec.resolution:.3f} m/pix")
        if self._pending_global:
            self._pending_global = False
            self.get_logger().info("Initializing with uniform distribution (requested before the map)")
            self.amcl.global_localization()
        elif self._pending_pose is not None:
            pose, cov, source = self._pending_pose
            self._pending_pose = None
            self._initial_pose(pose, cov, source)
        elif p.set_initial_pose and (previous is None or p.always_reset_initial_pose):
            self._initial_pose(Pose2D(p.initial_pose_x, p.initial_pose_y, p.initial_pose_yaw), None,
                               "parameters")
        elif previous is not None:
            last = Pose2D(previous.x, previous.y, previous.yaw)
            self._initial_pose(last, previous.covariance, "the last estimate")

    def _on_initial_pose(self, msg: PoseWithCovarianceStamped) -> None:
        self._initial_pose_msg(msg, "/initialpose")

    def _on_set_initial_pose(self, request: SetInitialPose.Request,
                             response: SetInitialPose.Response) -> SetInitialPose.Response:
        self._initial_pose_msg(request.pose, "set_initial_pose")
        return response

    def _initial_pose_msg(self, msg: PoseWithCovarianceStamped, source: str) -> None:
        frame = msg.header.frame_id.lstrip("/")
        if frame != self.params.global_frame_id:
            self.get_logger().warning(
                f"Ignoring initial pose from {source} in frame \"{msg.header.frame_id}\"; "
                f"initial poses must be in the global frame, \"{self.params.global_frame_id}\"")
            return
        try:
            pose = pose_to_2d(msg.pose.pose)
        except ValueError as error:
            self.get_logger().warning(f"Rejected initial pose from {source}: {error}")
            return
        applied = self._initial_pose(pose, covariance_3x3(msg.pose.covariance), source)
        if applied and self.health is not None:
            self.health.reset(source)

    def _initial_pose(self, pose: Pose2D, covariance: np.ndarray | None, source: str) -> bool:
        """Seed the filter at ``pose``; False when it waits for the map or is rejected."""
        if self.amcl is None:
            self.get_logger().info(f"Initial pose from {source} arrived before the map; "
                                   "it is applied when the map arrives")
            self._pending_pose, self._pending_global = (pose, covariance, source), False
            return False
        if self._seed is not None:  # the same pose draws the same cloud, whatever came before
            self.rng = self.amcl.rng = np.random.default_rng(self._seed)
        try:
            self.amcl.set_initial_pose(*pose, covariance)
        except ValueError as error:
            self.get_logger().warning(f"Rejected initial pose from {source}: {error}")
            return False
        self._last_scan_stamp = -math.inf
        self.get_logger().info(f"Setting pose from {source}: {pose[0]:.3f} {pose[1]:.3f} {pose[2]:.3f}")
        now = self._now()
        odom = self._odom_pose(None)
        self._publish_estimate(now, odom)
        return True

    # -- scans -------------------------------------------------------------------------------------
    def _on_scan(self, msg: LaserScanMsg) -> None:
        if self.amcl is None:
            self.get_logger().warning("Waiting for map....", throttle_duration_sec=WARN_PERIOD)
            return
        if not self.amcl.initialized:
            self.get_logger().warning(NO_POSE_WARNING, throttle_duration_sec=WARN_PERIOD)
            return
        if stamp_to_seconds(msg.header.stamp) <= self._last_scan_stamp:
            return  # older than (or the same as) a scan already used: out of order or replayed
        self._pending_scan = (msg, self._now())  # replaces an older scan still waiting
        self._process_pending_scan()
        if self._pending_scan is not None:
            self._pending_timer.reset()

    def _process_pending_scan(self) -> None:
        if self._pending_scan is None or self.amcl is None:
            self._pending_timer.cancel()
            return
        msg, received = self._pending_scan
        stamp = stamp_to_seconds(msg.header.stamp)
        laser = self._laser_pose(msg.header.frame_id)
        if laser is None:
            self._pending_scan = None
            self._pending_timer.cancel()
            return
        try:
            odom: Pose2D | None = self._lookup_pose(stamp)
        except ExtrapolationError as error:
            if "future" in str(error) and self._now() - received < SCAN_TF_WAIT:
                return  # odometry for this stamp may still be on its way
            odom = None
            self.get_logger().warning(f"Dropped the scan at {stamp:.3f} s: no odometry at its stamp "
                                      f"({error})", throttle_duration_sec=WARN_PERIOD)
        except TransformError as error:
            odom = None
            self.get_logger().warning(f"Couldn't determine robot's pose associated with laser scan: {error}",
                                      throttle_duration_sec=WARN_PERIOD)
        self._pending_scan = None
        self._pending_timer.cancel()
        if odom is not None:
            self._last_scan_stamp = stamp
            self._update(msg, stamp, odom, laser)

    def _now(self) -> float:
        """The node clock in s (sim time under use_sim_time)."""
        return float(self.get_clock().now().nanoseconds * 1e-9)

    def _lookup_pose(self, stamp: float | None) -> Pose2D:
        t = self.tf.lookup(self.params.odom_frame_id, self.params.base_frame_id, stamp)
        return pose_of(t)

    def _odom_pose(self, stamp: float | None) -> Pose2D | None:
        try:
            return self._lookup_pose(stamp)
        except TransformError:
            return None

    def _laser_pose(self, frame: str) -> Pose2D | None:
        frame = frame.lstrip("/")
        if frame not in self._laser_poses:
            try:
                t = self.tf.lookup(self.params.base_frame_id, frame, None)
            except TransformError as error:
                self.get_logger().error(f"Couldn't transform from {frame} to {self.params.base_frame_id}: "
                                        f"{error}", throttle_duration_sec=WARN_PERIOD)
                return None
            self._laser_poses[frame] = pose_of(t)
        return self._laser_poses[frame]

    def _update(self, msg: LaserScanMsg, stamp: float, odom: Pose2D, laser: Pose2D) -> None:
        assert self.amcl is not None
        ranges = np.asarray(msg.ranges, dtype=np.float64)
        ranges = np.where(np.isposinf(ranges), msg.range_max, ranges)  # REP 117: no return = max range
        try:
            scan = LaserScan(ranges, msg.angle_min, msg.angle_increment, msg.range_min, msg.range_max)
            result = self.amcl.update(odom, scan, laser)
        except ValueError as error:
            self.get_logger().warning(f"Dropped a scan: {error}", throttle_duration_sec=WARN_PERIOD)
            return
        if result.updated:
            self._publish_cloud()
            estimate = self._publish_estimate(stamp, odom)
            if estimate is not None and self.health is not None:
                self.health.observe(self.amcl, estimate, stamp)
        elif self._map_to_odom is not None:
            self._send_tf(stamp + self.params.transform_tolerance)

    # -- outputs -----------------------------------------------------------------------------------
    def _publish_estimate(self, stamp: float, odom: Pose2D | None) -> PoseEstimate | None:
        """Publish amcl_pose (and map→odom when ``odom`` is known); the estimate, None if not finite."""
        assert self.amcl is not None
        estimate = self.amcl.estimate()
        values = (estimate.x, estimate.y, estimate.yaw, *estimate.covariance.ravel())
        if not all(math.isfinite(v) for v in values):
            self.get_logger().warning("AMCL covariance or pose is NaN, likely due to an invalid "
                                      "configuration or faulty sensor measurements! Pose is not available!")
            return None
        self.pose_pub.publish(estimate_msg(estimate.x, estimate.y, estimate.yaw, estimate.covariance,
                                           self.params.global_frame_id, stamp))
        if odom is not None:
            self._map_to_odom = map_to_odom(Pose2D(estimate.x, estimate.y, estimate.yaw), odom)
            self._send_tf(stamp + self.params.transform_tolerance)
        return estimate

    def _publish_cloud(self) -> None:
        if self.amcl is None or self.cloud_pub.get_subscription_count() == 0:
            return
        stamp = self.get_clock().now().to_msg()
        self.cloud_pub.publish(particle_cloud_msg(self.amcl.particles, self.amcl.weights,
                                                  self.params.global_frame_id, stamp))

    def _send_tf(self, stamp: float) -> None:
        if self._map_to_odom is None or not self.params.tf_broadcast:
            return
        x, y, yaw = self._map_to_odom
        self._last_tf_stamp = stamp
        transform = Transform.from_xy_yaw(x, y, yaw)
        self.tf_broadcaster.send([transform_to_msg(transform, self.params.global_frame_id,
                                                   self.params.odom_frame_id, time_msg(stamp))])

    def _republish_tf(self) -> None:
        """Keep map→odom valid while scans stop (robot idle, sensor down): re-send the last estimate."""
        now = self._now()
        tolerance = self.params.transform_tolerance
        if self._map_to_odom is not None and now + tolerance / 2.0 > self._last_tf_stamp:
            self._send_tf(now + tolerance)

    # -- services ----------------------------------------------------------------------------------
    def _on_global_localization(self, request: Empty.Request, response: Empty.Response) -> Empty.Response:
        if self.amcl is None:
            self.get_logger().info("reinitialize_global_localization before the map: done when it arrives")
            self._pending_global, self._pending_pose = True, None
            return response
        self.get_logger().info("Initializing with uniform distribution")
        self.amcl.global_localization()
        self._last_scan_stamp = -math.inf
        return response

    def _on_nomotion_update(self, request: Empty.Request, response: Empty.Response) -> Empty.Response:
        if self.amcl is not None:
            self.amcl.request_nomotion_update()
            self.get_logger().info("Requesting no-motion update")
        return response


def main(argv: list[str] | None = None) -> int:
    """Run the node (``--ros-args --params-file config/nav2_params.yaml``); a lifecycle manager starts it."""
    return run_nodes(lambda: [AmclNode()], argv, role="amcl")


if __name__ == "__main__":
    raise SystemExit(main())
