"""``CpOdomTracker``: records the odometry path for undo motions and shows it on ``odom_tracker_path``.

Subscribes nav_msgs/Odometry on ``/odom`` (sensor-data QoS, best effort, which also matches reliable
publishers) and feeds ``OdomPath``; publishes the working path on ``odom_tracker_path`` and the
whole stack on ``odom_tracker_stacked_path`` (nav_msgs/Path, frame ``odom_frame``) at most every
``publish_period_s``, and only while someone subscribes to it.

Why the care: the path grows by one pose per odometry message (about 1,200 over the seed mission),
and building a PoseStamped for every pose of both paths at each publish grew to 30 ms of wall time
per publish by the mission's end: the state machine's longest lockstep holds, slowing the whole
simulation (bench_mission). Each pose's PoseStamped is now built once and reused.
"""

from __future__ import annotations

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry, Path
from rclpy.qos import qos_profile_sensor_data

from ros_tools.geometry import yaw_of
from smacc_py.clients.cl_nav2z.cp_pose import make_header, make_pose_stamped
from smacc_py.clients.cl_nav2z.geometry import Pose2D
from smacc_py.clients.cl_nav2z.odom_path import OdomPath, OdomTrackerParams, WorkingMode
from smacc_py.core import ISmaccComponent
from smacc_py.ros.context import ros_context


class CpOdomTracker(ISmaccComponent):
    """Odometry path recorder with SMACC2's working modes (``WorkingMode``)."""

    def __init__(
        self,
        odom_topic: str = "/odom",
        odom_frame: str = "odom",
        params: OdomTrackerParams | None = None,
        publish_period_s: float = 0.2,
    ) -> None:
        self.odom_topic, self.odom_frame = odom_topic, odom_frame
        self.paths = OdomPath(params)
        self.publish_period_s = publish_period_s
        self._last_publish_s = -1e9
        self.last_pose: Pose2D | None = None
        self._pose_msgs: dict[Pose2D, PoseStamped] = {}  # recorded pose -> its message, reused

    def on_initialize(self) -> None:
        ctx = ros_context(self.sm)
        self._path_pub = ctx.node.create_publisher(Path, "odom_tracker_path", 1)
        self._stacked_pub = ctx.node.create_publisher(Path, "odom_tracker_stacked_path", 1)
        self._sub = ctx.node.create_subscription(
            Odometry,
            self.odom_topic,
            self._on_odom,
            qos_profile_sensor_data,
        )

    def _on_odom(self, msg: Odometry) -> None:
        p = msg.pose.pose.position
        pose = (p.x, p.y, yaw_of(msg.pose.pose.orientation))
        self.last_pose = pose
        if self.paths.feed(pose):
            now = self.sm.now()
            if now - self._last_publish_s >= self.publish_period_s:
                self._last_publish_s = now
                self.publish()

    def publish(self) -> None:
        """Publish the working and stacked paths now (each only if someone subscribes to it)."""
        known, self._pose_msgs = self._pose_msgs, {}
        if self._path_pub.get_subscription_count() > 0:
            self._path_pub.publish(self._path_msg(self.paths.path(), known))
        if self._stacked_pub.get_subscription_count() > 0:
            self._stacked_pub.publish(self._path_msg(self.paths.stacked_path(), known))

    def _path_msg(self, poses: list[Pose2D], known: dict[Pose2D, PoseStamped]) -> Path:
        """A Path of ``poses``, reusing the messages of ``known``; keeps the messages it used for the next
        publish (the poses dropped from the paths since are forgotten)."""
        kept = self._pose_msgs
        for pose in poses:
            if pose not in kept:
                kept[pose] = known.get(pose) or make_pose_stamped(self.odom_frame, *pose)
        return Path(header=make_header(self.odom_frame, self.sm.now()), poses=[kept[pose] for pose in poses])

    # SMACC2 API, snake_case
    def set_working_mode(self, mode: WorkingMode) -> None:
        """RECORD_PATH, CLEAR_PATH or IDLE."""
        self.paths.set_mode(mode)

    def push_path(self, name: str = "") -> None:
        """Start a new working path."""
        self.paths.push_path(name)

    def pop_path(self) -> list[Pose2D]:
        """Drop the working path and return it."""
        path = self.paths.pop_path()
        self.publish()
        return path

    def clear_path(self) -> None:
        """Empty the working path."""
        self.paths.clear_path()
        self.publish()

    def path(self) -> list[Pose2D]:
        """The working path (odom frame)."""
        return self.paths.path()
