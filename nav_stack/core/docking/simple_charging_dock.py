"""opennav_docking's SimpleChargingDock (and SimpleNonChargingDock), without ROS.

A dock plugin answers four questions for the docking server: where to stage before the approach
(``staging_pose``), where the dock really is (``refined_pose``, from an external detection or the
database pose), whether the robot is docked (``is_docked``) and whether it charges (``is_charging``).

**Refined pose** (Nav2 Jazzy's ``getRefinedPose``). A detector publishes the pose of a tag P_tag
(``detected_dock_pose``, any frame; the node brings it into the fixed frame through TF at its stamp).
The detection must be younger than ``external_detection_timeout``. It is low-pass filtered
(``filter_coef``: position exponentially, orientation by slerp; restarted after a gap longer than the
timeout). Then the dock pose is, in Nav2's order:

1. orientation: q = q_tag · q_offset, with q_offset = R_y(pitch) · R_x(roll) · R_z(yaw) of the
   ``external_detection_rotation_*`` parameters (Jazzy builds it with tf2's ``setEuler(pitch, roll,
   yaw)``); only the heading of q is kept (roll and pitch dropped);
2. position: p_tag + R_z(heading) · (tx, ty), z = 0, with ``external_detection_translation_x/y``.

So the translation is applied in the *flattened dock frame*, after the rotation, not in the tag
frame: P_dock = Flat(p_tag, q_tag · q_offset) ∘ (tx, ty, 0). It is not P_tag · T_offset (which
would move along the tag's axes; with AprilTag axes and the Jazzy values that is sideways).

**Docked**: the robot base is closer than ``docking_threshold`` (m, position only, heading ignored) to
the last refined dock pose; with ``use_stall_detection``, the averaged |velocity| of
``stall_joint_names`` is below ``stall_velocity_threshold`` while their |effort| is above
``stall_effort_threshold`` instead. **Charging**: with ``use_battery_status``, the last
sensor_msgs/BatteryState ``current`` is above ``charging_threshold`` (A); otherwise docked counts as
charging. A non-charging dock (``is_charger`` False) never charges and is never waited for.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from nav_stack.core.docking.errors import FrameUnavailable
from nav_stack.core.docking.spatial import Pose3D, Quaternion, about_axis, multiply, slerp
from nav_stack.core.geometry import Pose2D, normalize_angle, yaw_or_nan

#: s a detection may wait for its transform (Nav2's canTransform timeout); meanwhile the last refined
#: pose stands. Nav2 blocks for it; a timer callback cannot, so the next cycle tries again.
TF_WAIT_S = 0.2
SIMPLE_CHARGING_DOCK = "SimpleChargingDock"
SIMPLE_NON_CHARGING_DOCK = "SimpleNonChargingDock"


@dataclass(frozen=True)
class SimpleChargingDockParams:
    """``<dock_plugin>.*`` parameters, Nav2 Jazzy's names and code defaults (nav2_params.yaml sets
    use_external_detection_pose true, use_battery_status false, translation_x -0.18, pitch -1.57).

    Units: m, rad, s, A; velocity and effort thresholds in the joint_states units.
    """

    use_battery_status: bool = True
    use_external_detection_pose: bool = False
    external_detection_timeout: float = 1.0
    external_detection_translation_x: float = -0.20
    external_detection_translation_y: float = 0.0
    external_detection_rotation_yaw: float = 0.0
    external_detection_rotation_pitch: float = 1.57
    external_detection_rotation_roll: float = -1.57
    filter_coef: float = 0.1
    charging_threshold: float = 0.5
    use_stall_detection: bool = False
    stall_joint_names: tuple[str, ...] = ()
    stall_velocity_threshold: float = 1.0
    stall_effort_threshold: float = 1.0
    docking_threshold: float = 0.05
    staging_x_offset: float = -0.7
    staging_yaw_offset: float = 0.0

    def __post_init__(self) -> None:
        numbers = {name: getattr(self, name) for name in (
            "external_detection_timeout", "external_detection_translation_x",
            "external_detection_translation_y",
            "external_detection_rotation_yaw", "external_detection_rotation_pitch",
            "external_detection_rotation_roll", "filter_coef", "charging_threshold", "docking_threshold",
            "staging_x_offset", "staging_yaw_offset")}
        bad = {name: value for name, value in numbers.items() if not math.isfinite(value)}
        if bad:
            raise ValueError(f"must be finite: {bad}")
        if self.external_detection_timeout <= 0.0:
            raise ValueError(f"external_detection_timeout must be > 0 s, got "
                             f"{self.external_detection_timeout}")
        if not self.filter_coef <= 1.0:
            raise ValueError(f"filter_coef must be <= 1 (<= 0 disables the filter), got {self.filter_coef}")
        if self.docking_threshold <= 0.0:
            raise ValueError(f"docking_threshold must be > 0 m, got {self.docking_threshold}")
        if self.use_stall_detection and not self.stall_joint_names:
            raise ValueError("stall_joint_names cannot be empty when use_stall_detection is true")

    def offset_rotation(self) -> Quaternion:
        """q_offset = R_y(pitch) · R_x(roll) · R_z(yaw) (Jazzy's ``setEuler(pitch, roll, yaw)``)."""
        return multiply(multiply(about_axis("y", self.external_detection_rotation_pitch),
                                 about_axis("x", self.external_detection_rotation_roll)),
                        about_axis("z", self.external_detection_rotation_yaw))


@dataclass(frozen=True)
class Detection:
    """A detected tag pose (m, unit quaternion) in ``frame`` at ``stamp`` (s, node clock)."""

    pose: Pose3D
    frame: str
    stamp: float


def dock_pose_from_tag(tag: Pose3D, params: SimpleChargingDockParams) -> Pose2D:
    """The dock pose from a tag pose in the same frame (steps 1 and 2 of the module docstring)."""
    yaw = yaw_or_nan(*multiply(tag.orientation, params.offset_rotation()))
    tx, ty = params.external_detection_translation_x, params.external_detection_translation_y
    return Pose2D(tag.x + math.cos(yaw) * tx - math.sin(yaw) * ty,
                  tag.y + math.sin(yaw) * tx + math.cos(yaw) * ty, yaw)


class PoseFilter:
    """Nav2's PoseFilter: exponential smoothing of detections (``coef`` of the new one), restarted when
    the frame changes or ``timeout`` s passed since the last one; ``coef`` <= 0 passes them through."""

    def __init__(self, coef: float, timeout: float) -> None:
        self.coef, self.timeout = coef, timeout
        self._state: Detection | None = None

    def update(self, measured: Detection) -> Detection:
        state, c = self._state, self.coef
        if c <= 0.0:
            return measured
        if state is None or measured.stamp - state.stamp > self.timeout or measured.frame != state.frame:
            self._state = measured
            return measured
        old, new = state.pose, measured.pose
        x, y, z = ((1.0 - c) * a + c * b for a, b in zip(old[:3], new[:3], strict=True))
        q = slerp(old.orientation, new.orientation, c)
        self._state = Detection(Pose3D(x, y, z, *q), measured.frame, measured.stamp)
        return self._state


class SimpleChargingDock:
    """One dock plugin instance (``dock_plugins`` entry ``name``); the node feeds its inputs."""

    def __init__(self, name: str, params: SimpleChargingDockParams, is_charger: bool = True) -> None:
        self.name, self.params, self.is_charger = name, params, is_charger
        self.dock_pose: Pose2D | None = None  # last refined (or database) dock pose ...
        self.dock_frame = ""  # ... in this frame ("" until known)
        self.detection: Detection | None = None  # latest detected_dock_pose, as received
        self.filtered: Detection | None = None  # latest filtered detection, in the fixed frame
        self.failure = ""  # why the last refined_pose returned None
        self._battery_charging = False
        self._stalled = False
        self._filter = PoseFilter(params.filter_coef, params.external_detection_timeout)

    # -- inputs -------------------------------------------------------------------------------------
    def on_detection(self, detection: Detection) -> None:
        self.detection = detection

    def on_battery_current(self, current: float) -> None:
        """sensor_msgs/BatteryState ``current`` (A, positive while charging)."""
        self._battery_charging = current > self.params.charging_threshold

    def on_joint_state(self, names: Sequence[str], velocities: Sequence[float], efforts: Sequence[float]
                       ) -> None:
        """sensor_msgs/JointState, for stall detection (joints missing velocity or effort count as 0)."""
        wanted = self.params.stall_joint_names
        speed = effort = 0.0
        for i, joint in enumerate(names):
            if joint in wanted:
                speed += abs(velocities[i]) if i < len(velocities) else 0.0
                effort += abs(efforts[i]) if i < len(efforts) else 0.0
        count = max(len(wanted), 1)
        self._stalled = (speed / count < self.params.stall_velocity_threshold
                         and effort / count > self.params.stall_effort_threshold)

    # -- the plugin interface -------------------------------------------------------------------------
    def staging_pose(self, dock_pose: Pose2D, frame: str) -> Pose2D:
        """The staging pose (in ``frame``) of a dock at ``dock_pose``; without external detection the
        dock pose becomes the tracked one (the start of a docking, as in Nav2)."""
        if not self.params.use_external_detection_pose:
            self.dock_pose, self.dock_frame = dock_pose, frame
        x, y, yaw = dock_pose
        offset = self.params.staging_x_offset
        return Pose2D(x + math.cos(yaw) * offset, y + math.sin(yaw) * offset,
                      normalize_angle(yaw + self.params.staging_yaw_offset))

    def refined_pose(self, estimate: Pose2D, frame: str, now: float,
                     to_frame: Callable[[Detection, str], Pose3D]) -> Pose2D | None:
        """The dock pose in ``frame`` (the fixed frame), or None with :attr:`failure` saying why.

        Without external detection it is ``estimate``. ``to_frame`` expresses a detection in a frame at
        its stamp, raising FrameUnavailable when TF cannot (yet).
        """
        if not self.params.use_external_detection_pose:
            self.dock_pose, self.dock_frame = estimate, frame
            return estimate
        detection = self.detection
        if detection is None:
            return self._fail("no detected_dock_pose received yet")
        age = now - detection.stamp
        if age > self.params.external_detection_timeout:
            return self._fail(f"the last detected_dock_pose is {age:.2f} s old "
                              f"(external_detection_timeout {self.params.external_detection_timeout} s)")
        try:
            pose = detection.pose if detection.frame == frame else to_frame(detection, frame)
        except FrameUnavailable as error:
            if age <= TF_WAIT_S and self.dock_pose is not None and self.dock_frame == frame:
                return self.dock_pose  # its transform may still come (see TF_WAIT_S)
            return self._fail(f"cannot transform detected_dock_pose from '{detection.frame}' to '{frame}': "
                              f"{error}")
        self.filtered = self._filter.update(Detection(pose, frame, detection.stamp))
        self.dock_pose, self.dock_frame = dock_pose_from_tag(self.filtered.pose, self.params), frame
        self.failure = ""
        return self.dock_pose

    def is_docked(self, robot: Pose2D | None) -> bool:
        """Whether the robot (its pose in :attr:`dock_frame`; None when unknown) is docked."""
        if self.params.use_stall_detection:
            return self._stalled
        if self.dock_pose is None or robot is None:
            return False
        distance = math.hypot(robot.x - self.dock_pose.x, robot.y - self.dock_pose.y)
        return distance < self.params.docking_threshold

    def is_charging(self, robot: Pose2D | None) -> bool:
        """Whether the robot charges (never, on a non-charging dock)."""
        if not self.is_charger:
            return False
        return self._battery_charging if self.params.use_battery_status else self.is_docked(robot)

    def has_stopped_charging(self, robot: Pose2D | None) -> bool:
        return not self.is_charging(robot)

    def _fail(self, reason: str) -> Pose2D | None:
        """Record why no refined pose exists; None (for ``return self._fail(...)``)."""
        self.failure = reason
        return None
