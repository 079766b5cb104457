"""Dock detection: the tag's pose in base_link when in view, range and line of sight; Nav2's
SimpleChargingDock rule turns it back into the contact pose; nothing otherwise; seeded noise.

The rule is written out here with plain matrices (not sim2d's nav2_dock_pose), as opennav_docking's
getRefinedPose applies it: yaw of R_tag · R_off, then the tag's position moved by t along that yaw.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.dock_detection import DockDetectionParams, TagDetection, nav2_dock_pose
from sim2d.core.robot import TB4, WAFFLE, Pose2D
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.spatial import from_quaternion, rotation_rpy
from tests.unit.sim2d.conftest import room_with_docks, sim_in

DOCK = {"id": "home", "type": "create3_dock", "pose": [1.75, 0.0, 0.0]}   # 0.25 m from the east wall
EXACT = DockDetectionParams(position_stddev=0.0, yaw_stddev=0.0)
R_OFF = rotation_rpy(-1.57, -1.57, 0.0)       # nav2_params.yaml (Jazzy): roll -1.57, pitch -1.57, yaw 0
T = np.array([-0.18, 0.0])                   # external_detection_translation_x, _y


def _nav2_rule(detection: TagDetection) -> tuple[float, float, float, np.ndarray]:
    """(x, y, yaw) of the dock Nav2 derives from ``detection`` and the full rotation R_tag · R_off."""
    rotation = from_quaternion(detection.orientation) @ R_OFF
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    c, s = math.cos(yaw), math.sin(yaw)
    x, y, _ = detection.position
    return x + c * T[0] - s * T[1], y + s * T[0] + c * T[1], yaw, rotation


def _in_base_link(robot: Pose2D, point: Pose2D) -> tuple[float, float, float]:
    c, s = math.cos(robot.yaw), math.sin(robot.yaw)
    dx, dy = point.x - robot.x, point.y - robot.y
    return c * dx + s * dy, -s * dx + c * dy, math.remainder(point.yaw - robot.yaw, 2.0 * math.pi)


def _detect(pose: Pose2D, params: DockDetectionParams = EXACT, robot=TB4, docks=(DOCK,),
            seed: int = 0) -> tuple[Simulator, TagDetection | None]:
    sim = sim_in(room_with_docks(*docks), pose, robot=robot, seed=seed, dock_detection=params)
    return sim, sim.detect_dock()


@pytest.mark.parametrize("pose", [Pose2D(1.05, 0.0, 0.0), Pose2D(0.6, 0.35, -0.3), Pose2D(1.2, -0.3, 0.5),
                                  Pose2D(1.6, 0.02, 0.05)], ids=str)
def test_seen_tag_composes_back_to_the_contact_pose(pose: Pose2D) -> None:
    sim, detection = _detect(pose)
    assert detection is not None and detection.dock_id == "home"
    x, y, yaw, rotation = _nav2_rule(detection)
    assert (x, y, yaw) == pytest.approx(_in_base_link(pose, Pose2D(1.75, 0.0, 0.0)), abs=1e-9)
    # the composed frame is level (1.57 on both sides), and the tag stands 0.1 m above the floor
    assert rotation[2, 2] == pytest.approx(1.0, abs=1e-9)
    assert detection.position[2] == pytest.approx(0.1 - TB4.base_link_z)
    assert nav2_dock_pose(detection.position, from_quaternion(detection.orientation),
                          sim.docks[0].type.tag) == pytest.approx(Pose2D(x, y, yaw))


def test_tag_axes_z_into_the_dock_x_to_its_left_y_up() -> None:
    _, detection = _detect(Pose2D(1.05, 0.0, 0.0))            # straight in front: base_link = dock axes
    assert detection is not None
    axes = from_quaternion(detection.orientation)
    assert axes[:, 2] == pytest.approx([1.0, 0.0, 0.0], abs=2e-3)      # z: into the dock (+x)
    assert axes[:, 0] == pytest.approx([0.0, 1.0, 0.0], abs=2e-3)      # x: the dock's left
    assert axes[:, 1] == pytest.approx([0.0, 0.0, 1.0], abs=2e-3)      # y: up
    assert detection.position[:2] == pytest.approx((0.7 + 0.18, 0.0))  # 0.18 m beyond the contact pose


def test_the_offset_is_applied_along_the_dock_not_in_the_tag_frame() -> None:
    """P_tag · [R_off | t] (t in the tag frame) would put the dock 0.18 m to the side: Nav2 does not."""
    _, detection = _detect(Pose2D(1.05, 0.0, 0.0))
    assert detection is not None
    r_tag = from_quaternion(detection.orientation)
    naive = np.array(detection.position) + r_tag @ np.array([T[0], T[1], 0.0])
    assert naive[:2] == pytest.approx((0.88, -0.18), abs=2e-3)          # sideways, not at (0.7, 0)


@pytest.mark.parametrize(("pose", "why"), [
    (Pose2D(1.05, 0.0, math.pi), "facing away"),
    (Pose2D(1.05, 0.0, 0.7), "turned beyond half the 1.25 rad field of view"),
    (Pose2D(-1.9, 0.0, 0.0), "beyond max_range"),
    (Pose2D(1.6, 1.3, -1.29), "seen from the side, 74° off the tag normal (max_view_angle 69°)"),
])
def test_nothing_outside_the_field_of_view_range_or_facing(pose: Pose2D, why: str) -> None:
    assert _detect(pose)[1] is None, why


def test_seen_from_the_side_within_max_view_angle() -> None:
    assert _detect(Pose2D(1.3, 1.3, -1.0))[1] is not None      # 60° off the tag normal


def test_nothing_below_min_range() -> None:
    assert _detect(Pose2D(1.6, 0.0, 0.0))[1] is not None
    assert _detect(Pose2D(1.6, 0.0, 0.0), DockDetectionParams(min_range=0.5))[1] is None


def test_nothing_from_behind_the_dock() -> None:
    middle = {"id": "middle", "type": "create3_dock", "pose": [0.0, 0.0, 0.0]}   # open floor all around
    assert _detect(Pose2D(1.0, 0.0, math.pi), docks=(middle,))[1] is None       # the dock's back
    assert _detect(Pose2D(-0.7, 0.0, 0.0), docks=(middle,))[1] is not None


def test_an_obstacle_or_another_dock_in_the_line_of_sight_hides_the_tag() -> None:
    sim, detection = _detect(Pose2D(0.5, 0.0, 0.0))
    assert detection is not None
    assert sim.drop_obstacle(DroppedObstacle(1.2, 0.0, 0.05))
    assert sim.detect_dock() is None
    other = {"id": "other", "type": "create3_dock", "pose": [0.9, 0.0, 0.0]}   # its body at x ≈ 1.08
    _, hidden = _detect(Pose2D(0.2, 0.0, 0.0), docks=(DOCK, other))
    assert hidden is not None and hidden.dock_id == "other"                   # the nearer one is seen


def test_the_dock_s_own_body_never_hides_its_tag() -> None:
    # on a waffle the body's face (0.092 m) is nearer than the tag (0.18 m): the tag is mounted on the dock
    sim, detection = _detect(Pose2D(1.45, 0.0, 0.0), robot=WAFFLE)
    assert detection is not None
    assert sim.docks[0].face_distance(WAFFLE) < 0.18


def test_noise_is_gaussian_and_reproducible_with_the_seed() -> None:
    params = DockDetectionParams()
    assert (params.position_stddev, params.yaw_stddev) == (0.005, 0.01)

    def samples(seed: int, count: int = 2000) -> np.ndarray:
        sim, _ = _detect(Pose2D(1.05, 0.0, 0.0), params, seed=seed)
        rows = []
        for _ in range(count):
            detection = sim.detect_dock()
            assert detection is not None
            x, y, yaw, _ = _nav2_rule(detection)
            rows.append((*detection.position[:2], yaw, x, y))
        return np.array(rows)

    first, again, other = samples(3), samples(3), samples(4)
    assert np.array_equal(first, again) and not np.array_equal(first, other)
    assert first[:, :2].mean(axis=0) == pytest.approx((0.88, 0.0), abs=5e-4)
    assert first[:, 0].std() == pytest.approx(0.005, rel=0.1)
    assert first[:, 2].std() == pytest.approx(0.01, rel=0.1)
    # the dock Nav2 derives stays within the noise: 4σ of position plus 0.18 m times 4σ of yaw
    assert np.abs(first[:, 3] - 0.7).max() < 4 * 0.005 + 0.18 * 4 * 0.01
    assert np.abs(first[:, 4]).max() < 4 * 0.005 + 0.18 * 4 * 0.01


def test_noise_stream_does_not_disturb_the_lidar_or_odometry() -> None:
    world, params = room_with_docks(DOCK), SimParams(initial_pose=Pose2D(1.05, 0.0, 0.0))
    plain = Simulator(world, TB4, params, np.random.default_rng(5))
    detecting = Simulator(world, TB4, params, np.random.default_rng(5))
    for _ in range(5):
        assert detecting.detect_dock() is not None
    assert np.array_equal(plain.scan(), detecting.scan())
