"""amcl_init_pose_publisher: the seed project's initial pose node, made reliable.

Why: AMCL in Jazzy starts without a pose (set_initial_pose false), so someone must publish
/initialpose. The seed's C++ node published once as soon as a subscriber existed; a message sent
before AMCL has its map is applied late or lost. This node does what BasicNavigator.setInitialPose
plus waitUntilNav2Active do: publish (frame ``map``) once AMCL listens, re-publish every
``republish_period`` until /amcl_pose reports a pose within ``position_tolerance`` /
``yaw_tolerance`` of the requested one, or until ``timeout`` runs out.

Parameters: x (-2.0 m), y (-0.5 m), yaw (0.0 rad), covariance (0.25: the x, y and yaw variances),
republish_period (1.0 s), timeout (60.0 s), position_tolerance (0.5 m), yaw_tolerance (0.5 rad),
exit_when_done (True; False keeps the node idle), and for the re-send after a respawn
resend_after_restart (False), global_frame_id (map), odom_frame_id (odom), base_frame_id
(base_footprint). Times are wall-clock seconds (a steady timer:
discovery and AMCL's start-up are wall-time matters). Nothing waits in a callback: a 0.1 s timer
publishes and checks the timeout, the /amcl_pose callback confirms.
Exit code of main(): 0 when confirmed, 1 on timeout.

After a respawn (``resend_after_restart``, set by nav-bringup when it respawns processes): the node
stays up, listens to TF, and when a new /amcl_pose publisher appears in the graph (AMCL creates it at
configure: a respawned AMCL, or one its manager reset), publishes the robot's last known pose on
/initialpose until the new AMCL confirms it. That pose is the dead AMCL's last map → odom composed with
the odometry's odom → ``base_frame_id`` now: the robot rolls on after AMCL dies, and AMCL publishes
/amcl_pose only after ``update_min_d`` of travel, so its last /amcl_pose lags by up to 0.25 m plus
the roll (the killed-navigation scenario measured 0.52 m off on the new AMCL's first pose). The last
/amcl_pose is the fallback when TF cannot tell. The graph is polled (RESTART_POLL_S) rather than
AMCL's ``transition_event`` heard: a new process's event is often sent before DDS has matched it.
Why this and not AMCL's own memory: Nav2's AMCL re-seeds from its last known
pose when it is reset inside a living process (``always_reset_initial_pose`` false; ours does too,
amcl_node), but a respawned AMCL process starts empty, and Nav2's other answer, ``set_initial_pose``
with the ``initial_pose`` parameters, would put the robot back at its start pose. The pose is sent
with ``covariance`` (not AMCL's last, tighter one): the robot may have rolled on while AMCL was gone.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.clock import Clock, ClockType
from rclpy.node import Node

from nav_stack.core.geometry import angle_diff, compose, yaw_or_nan
from nav_stack.ros.common.conversions import pose_from_2d
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import DEFAULT, LATCHED
from ros_tools.runtime.runner import run_nodes, split_runner_flags

NODE_NAME = "amcl_init_pose_publisher"
RESTART_POLL_S = 0.5  # s (steady) between two looks for a new /amcl_pose publisher


@dataclass(frozen=True)
class InitialPoseParams:
    x: float = -2.0
    y: float = -0.5
    yaw: float = 0.0
    covariance: float = 0.25
    republish_period: float = 1.0
    timeout: float = 60.0
    position_tolerance: float = 0.5
    yaw_tolerance: float = 0.5
    exit_when_done: bool = True
    #: Not in Nav2 (nav2_bringup has no initial-pose node): after AMCL restarts, send it its last pose.
    resend_after_restart: bool = False
    global_frame_id: str = "map"
    odom_frame_id: str = "odom"
    base_frame_id: str = "base_footprint"

    def __post_init__(self) -> None:
        for name in ("x", "y", "yaw"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)}")
        for name in ("global_frame_id", "odom_frame_id", "base_frame_id"):
            if not getattr(self, name).strip("/"):
                raise ValueError(f"{name} must name a frame, got {getattr(self, name)!r}")
        for name in ("covariance", "republish_period", "timeout", "position_tolerance", "yaw_tolerance"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")


class InitialPosePublisher(Node):
    """Publishes /initialpose until AMCL confirms it; ``done`` is None, True (confirmed) or False."""

    def __init__(self, **kwargs: object) -> None:
        super().__init__(NODE_NAME, **kwargs)  # type: ignore[arg-type]
        self.params = declare_dataclass(self, InitialPoseParams)
        self.done: bool | None = None
        self.published = 0
        self._started = time.monotonic()
        self._pub = self.create_publisher(PoseWithCovarianceStamped, "initialpose", DEFAULT)
        self.create_subscription(PoseWithCovarianceStamped, "amcl_pose", self._on_amcl_pose, LATCHED)
        self._last_publish = -math.inf
        self._target = (self.params.x, self.params.y, self.params.yaw)  # m, m, rad: the pose to confirm
        self._last_amcl: tuple[float, float, float] | None = None  # the newest /amcl_pose (m, m, rad)
        self.resent = 0  # restarts of AMCL answered with its last pose
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(0.1, self._tick, clock=self._steady)
        self._amcl_publishers: set[bytes] = set()  # gids of every /amcl_pose publisher seen so far
        self._frames: Frames | None = None  # TF, only to re-send the last known pose after a restart
        if self.params.resend_after_restart:
            self._frames = Frames(self, self.params.base_frame_id.strip("/"))
            self.create_timer(RESTART_POLL_S, self._watch_amcl, clock=self._steady)

    def _message(self) -> PoseWithCovarianceStamped:
        p = self.params
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = "map"
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.pose.pose = pose_from_2d(*self._target)
        covariance = [0.0] * 36
        covariance[0] = covariance[7] = covariance[35] = p.covariance
        msg.pose.covariance = covariance
        return msg

    def _tick(self) -> None:
        if self.done is not None:
            return
        now = time.monotonic()
        if now - self._started > self.params.timeout:
            self.get_logger().error(f"AMCL did not confirm the initial pose within "
                                    f"{self.params.timeout:.1f} s ({self.published} publications)")
            self._finish(False)
            return
        if self._pub.get_subscription_count() == 0 or now - self._last_publish < self.params.republish_period:
            return
        self._pub.publish(self._message())
        self._last_publish = now
        self.published += 1
        x, y, yaw = self._target
        self.get_logger().info(f"Published initial pose ({x:.2f}, {y:.2f}, {yaw:.2f}) on /initialpose")

    def _on_amcl_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = yaw_or_nan(q.x, q.y, q.z, q.w)
        if self.done is not None or self.published == 0:
            if self.done and math.isfinite(yaw):
                self._last_amcl = (p.x, p.y, yaw)
            return  # a latched pose from before our request says nothing about it
        distance = math.hypot(p.x - self._target[0], p.y - self._target[1])
        yaw_error = abs(angle_diff(yaw, self._target[2]))
        if distance <= self.params.position_tolerance and yaw_error <= self.params.yaw_tolerance:
            self.get_logger().info(f"AMCL confirmed the initial pose "
                                   f"({distance:.3f} m, {yaw_error:.3f} rad off)")
            self._finish(True)

    def _finish(self, confirmed: bool) -> None:
        self.done = confirmed
        self._timer.cancel()
        if confirmed:
            self._last_amcl = self._target
            self._new_amcl_publishers()  # the confirming AMCL's publisher is not a new one

    def _new_amcl_publishers(self) -> bool:
        """Whether /amcl_pose has a publisher not seen before (all seen ones are remembered: a dead
        process's publisher lingers in the graph for a while and must not count twice)."""
        infos = self.get_publishers_info_by_topic(self.resolve_topic_name("amcl_pose"))
        gids = {bytes(info.endpoint_gid) for info in infos}
        new = gids - self._amcl_publishers
        self._amcl_publishers |= gids
        return bool(new)

    def _watch_amcl(self) -> None:
        """A new AMCL (a respawn, or its manager's reset): send it its last pose."""
        if not self._new_amcl_publishers() or not self.done or self._last_amcl is None:
            return
        self._target = self._last_known_pose()
        self.done, self.published, self.resent = None, 0, self.resent + 1
        self._started, self._last_publish = time.monotonic(), -math.inf
        x, y, yaw = self._target
        self.get_logger().info(f"AMCL is back: sending its last pose ({x:.2f}, {y:.2f}, {yaw:.2f})")
        self._timer.reset()

    def _last_known_pose(self) -> tuple[float, float, float]:
        """The robot's pose in the map now (m, m, rad): the last map → odom AMCL sent before it died,
        composed with the latest odom → base; the last /amcl_pose when TF cannot tell."""
        assert self._last_amcl is not None and self._frames is not None
        p = self.params
        try:
            map_odom = self._frames.frame_pose(p.global_frame_id.strip("/"), p.odom_frame_id.strip("/"))
            odom_base = self._frames.robot_pose(p.odom_frame_id.strip("/"))
        except FrameError as error:
            self.get_logger().warning(f"the pose sent to the new AMCL is its last /amcl_pose: {error}")
            return self._last_amcl
        pose = compose(map_odom, odom_base)
        return (pose.x, pose.y, pose.yaw)


def main(argv: list[str] | None = None) -> int:
    """Run until AMCL confirms the pose (exit 0) or the timeout (exit 1); with exit_when_done false,
    or resend_after_restart true, stay until Ctrl-C or SIGTERM (0 if AMCL confirmed the pose, else 1).

    ``[--executor events|single] [--ros-args ...]``. Not a lockstep participant: it only watches.
    """

    _, executor_kind, rclpy_args = split_runner_flags(sys.argv if argv is None else argv, __doc__)

    def outcome(nodes: Sequence[Any]) -> int:
        return 0 if nodes and nodes[0].done else 1

    def finished(nodes: Sequence[Any]) -> int | None:
        node = nodes[0]
        stay = not node.params.exit_when_done or node.params.resend_after_restart
        return None if node.done is None or stay else outcome(nodes)

    return run_nodes(lambda: [InitialPosePublisher()], role=NODE_NAME, rclpy_args=rclpy_args,
                     executor=executor_kind, finished=finished, interrupted_code=outcome, lockstep=False)


if __name__ == "__main__":
    sys.exit(main())
