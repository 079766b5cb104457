"""SimpleChargingDock: staging pose, refined pose from a tag detection (Nav2 Jazzy's rule), the
detection filter and timeout, docked and charging decisions."""

from __future__ import annotations

import math

import pytest

from nav_stack.core.docking.errors import FrameUnavailable
from nav_stack.core.docking.simple_charging_dock import (
    Detection,
    PoseFilter,
    SimpleChargingDock,
    SimpleChargingDockParams,
    dock_pose_from_tag,
)
from nav_stack.core.docking.spatial import Pose3D, about_axis, compose, inverse, multiply, rotate
from nav_stack.core.geometry import Pose2D, yaw_from_quaternion
from tests.helpers.docking_world import JAZZY_DOCK, pose3d, tag_pose_for

DOCKS = [Pose2D(0.0, 0.0, 0.0), Pose2D(1.5, -2.0, 0.7), Pose2D(-3.0, 1.0, -2.9), Pose2D(0.3, 0.4, math.pi)]


def _no_tf(detection: Detection, frame: str) -> Pose3D:
    raise FrameUnavailable(f"no transform from '{detection.frame}' to '{frame}'")


@pytest.mark.parametrize("dock", DOCKS)
def test_a_tag_built_from_a_dock_pose_refines_back_to_it_with_the_jazzy_defaults(dock: Pose2D) -> None:
    tag = tag_pose_for(dock, JAZZY_DOCK)
    assert dock_pose_from_tag(tag, JAZZY_DOCK) == pytest.approx(dock, abs=1e-9)


def test_the_jazzy_offset_turns_the_tags_z_axis_into_the_dock_heading() -> None:
    """With roll = pitch = -1.57: dock x = tag z, dock y = tag x, dock z = tag y (a tag on the dock's face,
    z pointing into the dock); the translation -0.18 puts the dock pose 0.18 m in front of the tag."""
    q = JAZZY_DOCK.offset_rotation()
    assert rotate(q, (1.0, 0.0, 0.0)) == pytest.approx((0.0, 0.0, 1.0), abs=2e-3)
    assert rotate(q, (0.0, 1.0, 0.0)) == pytest.approx((1.0, 0.0, 0.0), abs=2e-3)
    # A tag 1 m ahead of the robot, facing it (tag z along +x of the robot frame).
    tag = Pose3D(1.0, 0.0, 0.2, *multiply(about_axis("y", math.pi / 2), about_axis("z", math.pi / 2)))
    dock = dock_pose_from_tag(tag, JAZZY_DOCK)
    assert dock == pytest.approx((0.82, 0.0, 0.0), abs=2e-3)


def test_the_translation_is_applied_in_the_flattened_dock_frame_not_the_tag_frame() -> None:
    """Nav2's rule is not P_tag · T_offset: composing in the tag frame would move along the tag's own
    axes (with the Jazzy rotation, sideways), and keep the height."""
    dock = Pose2D(2.0, 1.0, 0.5)
    tag = tag_pose_for(dock, JAZZY_DOCK)
    offset = Pose3D(JAZZY_DOCK.external_detection_translation_x, JAZZY_DOCK.external_detection_translation_y,
                    0.0, *JAZZY_DOCK.offset_rotation())
    composed = compose(tag, offset)
    assert math.hypot(composed.x - dock.x, composed.y - dock.y) > 0.1
    # the rotations agree
    assert yaw_from_quaternion(*composed.orientation) == pytest.approx(dock.yaw, abs=1e-9)


def test_roll_and_pitch_of_the_detection_are_dropped() -> None:
    """A tag tilted about the dock's heading (the detector's noise) gives the same heading and position."""
    dock = Pose2D(1.0, 2.0, 1.2)
    tag = tag_pose_for(dock, JAZZY_DOCK)
    tilted = tag.with_orientation(multiply(multiply(about_axis("z", dock.yaw), about_axis("x", 0.3)),
                                           multiply(about_axis("z", -dock.yaw), tag.orientation)))
    assert dock_pose_from_tag(tilted, JAZZY_DOCK) == pytest.approx(dock, abs=1e-9)


def test_jazzy_composes_the_rotation_offset_as_pitch_roll_yaw() -> None:
    """Jazzy builds q_offset with tf2's setEuler(pitch, roll, yaw) = R_y(pitch)·R_x(roll)·R_z(yaw)."""
    params = SimpleChargingDockParams(external_detection_rotation_roll=0.4,
                                      external_detection_rotation_pitch=-0.3,
                                      external_detection_rotation_yaw=1.1)
    q = multiply(multiply(about_axis("y", -0.3), about_axis("x", 0.4)), about_axis("z", 1.1))
    assert params.offset_rotation() == pytest.approx(q)


# -- the plugin -----------------------------------------------------------------------------------------
def _plugin(**overrides: object) -> SimpleChargingDock:
    values = {**JAZZY_DOCK.__dict__, "filter_coef": 0.0, **overrides}
    return SimpleChargingDock("simple_charging_dock", SimpleChargingDockParams(**values))


def test_staging_pose_is_offset_along_the_dock_heading() -> None:
    plugin = _plugin(staging_yaw_offset=0.2)
    staging = plugin.staging_pose(Pose2D(1.0, 1.0, math.pi / 2), "map")
    assert staging == pytest.approx((1.0, 0.3, math.pi / 2 + 0.2))
    assert plugin.dock_pose is None  # with external detection the database pose is not the tracked one
    blind = _plugin(use_external_detection_pose=False)
    blind.staging_pose(Pose2D(1.0, 1.0, 0.0), "map")
    assert (blind.dock_pose, blind.dock_frame) == (Pose2D(1.0, 1.0, 0.0), "map")


def test_refined_pose_needs_a_fresh_detection() -> None:
    plugin = _plugin()
    estimate = Pose2D(0.0, 0.0, 0.0)
    assert plugin.refined_pose(estimate, "odom", 10.0, _no_tf) is None
    assert "no detected_dock_pose" in plugin.failure
    dock = Pose2D(1.0, 0.5, 0.2)
    plugin.on_detection(Detection(tag_pose_for(dock, plugin.params), "odom", 10.0))
    assert plugin.refined_pose(estimate, "odom", 10.5, _no_tf) == pytest.approx(dock)
    assert plugin.refined_pose(estimate, "odom", 11.2, _no_tf) is None
    assert "1.20 s old (external_detection_timeout 1.0 s)" in plugin.failure


def test_refined_pose_goes_through_the_transform_at_the_detection_stamp() -> None:
    plugin = _plugin()
    robot = Pose2D(2.0, 1.0, 0.5)
    dock_in_odom = Pose2D(3.0, 1.5, 0.3)
    tag_in_odom = tag_pose_for(dock_in_odom, plugin.params)
    seen: list[tuple[str, str]] = []

    def to_odom(detection: Detection, frame: str) -> Pose3D:
        seen.append((detection.frame, frame))
        return compose(pose3d(robot), detection.pose)

    plugin.on_detection(Detection(compose(inverse(pose3d(robot)), tag_in_odom), "base_link", 5.0))
    assert plugin.refined_pose(Pose2D(0.0, 0.0, 0.0), "odom", 5.1, to_odom) == pytest.approx(dock_in_odom)
    assert seen == [("base_link", "odom")]
    # TF not there yet: the last refined pose stands for TF_WAIT_S, then the detection fails.
    plugin.on_detection(Detection(Pose3D(0.0, 0.0, 0.0), "base_link", 6.0))
    assert plugin.refined_pose(Pose2D(0.0, 0.0, 0.0), "odom", 6.1, _no_tf) == pytest.approx(dock_in_odom)
    assert plugin.refined_pose(Pose2D(0.0, 0.0, 0.0), "odom", 6.3, _no_tf) is None
    assert "cannot transform detected_dock_pose from 'base_link' to 'odom'" in plugin.failure


def test_the_filter_smooths_detections_and_restarts_after_a_gap() -> None:
    pose_filter = PoseFilter(coef=0.1, timeout=1.0)
    first = pose_filter.update(Detection(Pose3D(0.0, 0.0, 0.0), "odom", 0.0))
    assert first.pose == Pose3D(0.0, 0.0, 0.0)
    second = pose_filter.update(Detection(Pose3D(1.0, 0.0, 0.0, *about_axis("z", 1.0)), "odom", 0.1))
    assert second.pose[:3] == pytest.approx((0.1, 0.0, 0.0))
    assert yaw_from_quaternion(*second.pose.orientation) == pytest.approx(0.1)
    restarted = pose_filter.update(Detection(Pose3D(5.0, 0.0, 0.0), "odom", 2.0))
    assert restarted.pose.x == 5.0
    other_frame = pose_filter.update(Detection(Pose3D(7.0, 0.0, 0.0), "map", 2.1))
    assert other_frame.pose.x == 7.0
    assert PoseFilter(0.0, 1.0).update(Detection(Pose3D(3.0, 0.0, 0.0), "odom", 0.0)).pose.x == 3.0


def test_docked_is_within_the_threshold_of_the_refined_pose() -> None:
    plugin = _plugin()
    assert not plugin.is_docked(Pose2D(0.0, 0.0, 0.0))  # no dock pose yet
    plugin.on_detection(Detection(tag_pose_for(Pose2D(1.0, 0.0, 0.0), plugin.params), "odom", 0.0))
    plugin.refined_pose(Pose2D(0.0, 0.0, 0.0), "odom", 0.0, _no_tf)
    assert plugin.is_docked(Pose2D(0.96, 0.0, 2.0))  # position only: heading is not looked at
    assert not plugin.is_docked(Pose2D(0.94, 0.0, 0.0))
    assert not plugin.is_docked(None)
    assert plugin.is_charging(Pose2D(0.97, 0.0, 0.0))  # use_battery_status false: docked counts


def test_charging_from_the_battery_current() -> None:
    plugin = _plugin(use_battery_status=True)
    plugin.on_detection(Detection(tag_pose_for(Pose2D(1.0, 0.0, 0.0), plugin.params), "odom", 0.0))
    plugin.refined_pose(Pose2D(0.0, 0.0, 0.0), "odom", 0.0, _no_tf)
    assert not plugin.is_charging(Pose2D(1.0, 0.0, 0.0))  # docked but no current yet
    plugin.on_battery_current(0.6)
    assert plugin.is_charging(None) and not plugin.has_stopped_charging(None)
    plugin.on_battery_current(0.5)  # not above charging_threshold
    assert not plugin.is_charging(None)
    non_charger = SimpleChargingDock("pallet", plugin.params, is_charger=False)
    non_charger.on_battery_current(2.0)
    assert not non_charger.is_charging(None)


def test_stall_detection_decides_docked() -> None:
    plugin = _plugin(use_stall_detection=True, stall_joint_names=("left", "right"))
    plugin.on_joint_state(["left", "right", "caster"], [0.1, 0.2, 5.0], [1.5, 1.2, 0.0])
    assert plugin.is_docked(None)
    plugin.on_joint_state(["left", "right"], [2.0, 2.0], [1.5, 1.2])
    assert not plugin.is_docked(None)


def test_bad_plugin_parameters_are_refused() -> None:
    with pytest.raises(ValueError, match="docking_threshold must be > 0"):
        SimpleChargingDockParams(docking_threshold=0.0)
    with pytest.raises(ValueError, match="stall_joint_names cannot be empty"):
        SimpleChargingDockParams(use_stall_detection=True)
    with pytest.raises(ValueError, match="must be finite"):
        SimpleChargingDockParams(staging_x_offset=math.nan)
