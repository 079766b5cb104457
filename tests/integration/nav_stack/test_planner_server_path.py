"""planner_server's path_msg: the message of conversions.path_from_array, field by field and on the wire."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.action")

from builtin_interfaces.msg import Time
from nav_msgs.msg import Path
from rclpy.serialization import deserialize_message, serialize_message

from nav_stack.ros.conversions import path_from_array
from nav_stack.ros.planner_server import path_msg


@pytest.mark.parametrize("count", [1, 2, 317])
def test_path_msg_equals_path_from_array(count: int) -> None:
    rng = np.random.default_rng(count)
    poses = np.column_stack((rng.normal(0.0, 20.0, (count, 2)), rng.uniform(-math.pi, math.pi, count)))
    poses[0, 2] = math.pi  # the yaw at the wrap
    stamp = Time(sec=123, nanosec=456_000)
    fast, reference = path_msg(poses, "map", stamp), path_from_array(poses, "map", stamp)
    assert fast == reference
    assert deserialize_message(serialize_message(fast), Path) == reference
    assert [p.header for p in fast.poses] == [reference.header] * count


def test_a_later_path_leaves_an_earlier_one_unchanged() -> None:
    first = path_msg(np.zeros((3, 3)), "map", Time(sec=1))
    path_msg(np.ones((3, 3)), "odom", Time(sec=2))
    assert all(p.header.frame_id == "map" and p.header.stamp.sec == 1 for p in first.poses)
