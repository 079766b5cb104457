"""``CpAmcl``: talks to AMCL. Sets its initial pose (``initialpose``, PoseWithCovarianceStamped, QoS 10)
and hears its estimate (``amcl_pose``: reliable, transient local, depth 1, as nav2_amcl publishes it).

Why the component listens too: "AMCL took the pose" is only known from AMCL's next estimate, and a
behavior that waits for it (CbSetInitialPose) should not own a subscription of its own: the
component is the one ROS endpoint a test substitutes.

AMCL answers every initial pose it takes with an estimate at once, so a pose and its answer are a
request and its response. In lockstep, sim time waits for the answer (at most DISCOVERY_HOLD_S wall
s), and the pose is sent again every RESEND_WALL_S wall s meanwhile: a pose sent before DDS has
matched AMCL's subscription with this publisher is lost, and discovery takes wall time. Without the
hold, the sim ran on while the behavior republished on its sim-time period: StSetInitialPose lasted 0
to 1.34 s of sim time over 10 seed missions (to 11.2 s with a shorter discovery settle in the
runtime), and 0 s in all 10 with it (bench_mission, back to back).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.clock import Clock, ClockType
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from ros_tools.geometry import yaw_of
from smacc_py.clients.cl_nav2z.cp_pose import make_pose_stamped
from smacc_py.clients.cl_nav2z.geometry import Pose2D
from smacc_py.core import ISmaccComponent
from smacc_py.ros.components.signal import SmaccSignal
from smacc_py.ros.context import DISCOVERY_HOLD_S, hold_lockstep, ros_context

# Covariance of sm_nav2_gazebo_test_1's initial pose: σ² x = y = 0.25 m², yaw = 0.06 rad².
DEFAULT_COVARIANCE = (0.25, 0.25, 0.06)
AMCL_POSE_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)

RESEND_WALL_S = 0.25  # wall s between copies of an initial pose AMCL has not answered, while sim time waits
PoseListener = Callable[[Pose2D], None]


class CpAmcl(ISmaccComponent):
    """Publisher of the initial pose in ``frame_id`` (map); listener of AMCL's estimate.

    Attributes:
        published: every initial pose sent, (x, y, yaw).
        last_estimate: AMCL's latest estimate (x, y, yaw), None before the first.
        estimate_received: the signal ``listen`` connects to, emitted with every estimate.
    """

    def __init__(self, topic: str = "initialpose", frame_id: str = "map",
                 amcl_pose_topic: str = "amcl_pose") -> None:
        self.topic, self.frame_id, self.amcl_pose_topic = topic, frame_id, amcl_pose_topic
        self.published: list[Pose2D] = []
        self._unanswered: PoseWithCovarianceStamped | None = None  # the last pose sent, until an estimate
        self._unanswered_since = 0.0  # time.monotonic() it was first sent
        self._resend_timer: Any = None
        self.last_estimate: Pose2D | None = None
        self.estimate_received: SmaccSignal[Pose2D] = SmaccSignal("CpAmcl.estimate_received")

    def on_initialize(self) -> None:
        node = ros_context(self.sm).node
        self._pub = node.create_publisher(PoseWithCovarianceStamped, self.topic, 10)
        self._sub = node.create_subscription(PoseWithCovarianceStamped, self.amcl_pose_topic,
                                             self._on_amcl_pose, AMCL_POSE_QOS)
        self._resend_timer = node.create_timer(RESEND_WALL_S, self._resend_unanswered,
                                               clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._resend_timer.cancel()

    def set_initial_pose(
        self, x: float, y: float, yaw: float, covariance: tuple[float, float, float] = DEFAULT_COVARIANCE
    ) -> None:
        """Publish (x, y in m, yaw in rad) with variances (x, y in m², yaw in rad²), stamped now (machine
        clock)."""
        pose = make_pose_stamped(self.frame_id, x, y, yaw, stamp=self.sm.now())
        msg = PoseWithCovarianceStamped(header=pose.header)
        msg.pose.pose = pose.pose
        cov = [0.0] * 36
        cov[0], cov[7], cov[35] = covariance
        msg.pose.covariance = cov
        self._pub.publish(msg)
        self.published.append((float(x), float(y), float(yaw)))
        if self._resend_timer is not None:  # a ROS publisher (not a test's stand-in)
            self._unanswered, self._unanswered_since = msg, time.monotonic()
            hold_lockstep(self.sm, lambda: self._unanswered is None)
            self._resend_timer.reset()

    def _resend_unanswered(self) -> None:
        """Send the unanswered pose again while sim time waits for the answer (DISCOVERY_HOLD_S)."""
        if self._unanswered is None or time.monotonic() - self._unanswered_since > DISCOVERY_HOLD_S:
            self._resend_timer.cancel()
            return
        self._pub.publish(self._unanswered)

    def listen(self, listener: PoseListener) -> Callable[[], None]:
        """Call ``listener(x, y, yaw)`` with every estimate from now on; returns the unsubscribe call."""
        return self.estimate_received.connect(listener)

    def on_estimate(self, estimate: Pose2D) -> None:
        """Take one AMCL estimate: remember it and pass it to the listeners."""
        self._unanswered = None
        self.last_estimate = estimate
        self.estimate_received.emit(estimate)

    def _on_amcl_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p = msg.pose.pose.position
        self.on_estimate((p.x, p.y, yaw_of(msg.pose.pose.orientation)))
