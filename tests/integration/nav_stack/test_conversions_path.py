"""conversions.path_from_array / path_to_array against a Path built and read field by field.

The fast builder and reader fill and read the generated classes' slots (issue 44: a warehouse plan of
about a thousand poses is built once and read twice per replan); these tests pin them to the plain
constructors and to yaw_from_quaternion, in memory and after a trip over the wire (serialisation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg")

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, PoseStamped, Quaternion
from nav_msgs.msg import Path
from rclpy.serialization import deserialize_message, serialize_message

from nav_stack.core.geometry import quaternion_from_yaw, yaw_from_quaternion
from nav_stack.ros.common.conversions import path_from_array, path_to_array

STAMP = Time(sec=123, nanosec=456_000)


def reference_path(poses: np.ndarray, frame: str, stamp: Time) -> Path:
    """The Path built with the messages' constructors, one field at a time."""
    msg = Path()
    msg.header.frame_id, msg.header.stamp = frame, stamp
    for x, y, yaw in poses.tolist():
        stamped = PoseStamped()
        stamped.header.frame_id, stamped.header.stamp = frame, Time(sec=stamp.sec, nanosec=stamp.nanosec)
        qx, qy, qz, qw = quaternion_from_yaw(yaw)
        stamped.pose = Pose(position=Point(x=x, y=y, z=0.0), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw))
        msg.poses.append(stamped)
    return msg


def reference_array(path: Path, invalid_yaw: float) -> np.ndarray:
    """(N, 3) read pose by pose through the public fields and yaw_from_quaternion."""
    rows = []
    for stamped in path.poses:
        p, q = stamped.pose.position, stamped.pose.orientation
        try:
            yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
        except ValueError:
            yaw = invalid_yaw
        rows.append((p.x, p.y, yaw))
    return np.array(rows, dtype=np.float64).reshape(-1, 3)


def random_poses(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    poses = np.column_stack((rng.normal(0.0, 20.0, (count, 2)), rng.uniform(-math.pi, math.pi, count)))
    poses[0, 2] = math.pi  # the yaw at the wrap
    return poses


@pytest.mark.parametrize("count", [1, 2, 317])
def test_path_from_array_equals_the_field_by_field_path(count: int) -> None:
    poses = random_poses(count, count)
    fast, reference = path_from_array(poses, "map", STAMP), reference_path(poses, "map", STAMP)
    assert fast == reference
    on_the_wire = deserialize_message(serialize_message(fast), Path)
    assert on_the_wire == reference
    assert all(p.header.frame_id == "map" and p.header.stamp == STAMP for p in on_the_wire.poses)
    assert on_the_wire.header.frame_id == "map" and on_the_wire.header.stamp == STAMP


def test_a_later_path_leaves_an_earlier_one_unchanged() -> None:
    first = path_from_array(np.zeros((3, 3)), "map", Time(sec=1))
    path_from_array(np.ones((3, 3)), "odom", Time(sec=2))
    assert all(p.header.frame_id == "map" and p.header.stamp.sec == 1 for p in first.poses)


@pytest.mark.parametrize("invalid_yaw", [0.0, math.nan])
def test_path_to_array_equals_yaw_from_quaternion_bit_for_bit(invalid_yaw: float) -> None:
    """Unnormalised, negative, zero-norm, NaN and inf quaternions, read from the wire."""
    rng = np.random.default_rng(7)
    count = 400
    msg = Path()
    msg.header.frame_id = "odom"
    quaternions = rng.normal(0.0, 3.0, (count, 4))
    quaternions[::7] *= 1e-12  # below the normalisable norm
    quaternions[3::11, 2] = math.nan
    quaternions[5::13, 3] = math.inf
    quaternions[9] = 0.0
    for (x, y), (qx, qy, qz, qw) in zip(rng.normal(0.0, 30.0, (count, 2)).tolist(), quaternions.tolist(),
                                        strict=True):
        stamped = PoseStamped()
        stamped.pose.position.x, stamped.pose.position.y = x, y
        stamped.pose.orientation = Quaternion(x=qx, y=qy, z=qz, w=qw)
        msg.poses.append(stamped)
    received = deserialize_message(serialize_message(msg), Path)
    fast, reference = path_to_array(received, invalid_yaw), reference_array(received, invalid_yaw)
    assert fast.shape == (count, 3)
    np.testing.assert_array_equal(fast, reference)  # NaN == NaN here; every other bit must agree
    assert np.isnan(fast[9, 2]) == math.isnan(invalid_yaw)


def test_an_array_survives_the_round_trip() -> None:
    poses = random_poses(1000, 3)
    received = deserialize_message(serialize_message(path_from_array(poses, "map", STAMP)), Path)
    back = path_to_array(received)
    np.testing.assert_array_equal(back, reference_array(received, 0.0))
    np.testing.assert_array_equal(back[:, :2], poses[:, :2])
    wrapped = np.angle(np.exp(1j * (back[:, 2] - poses[:, 2])))
    assert np.abs(wrapped).max() < 1e-12


def test_an_empty_path_reads_as_no_poses() -> None:
    assert path_to_array(Path()).shape == (0, 3)
    assert path_to_array(path_from_array(np.zeros((0, 3)), "map", STAMP)).shape == (0, 3)
