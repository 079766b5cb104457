"""The yaw of a geometry_msgs/Quaternion, and the reverse (ros_tools.geometry)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest
from geometry_msgs.msg import Quaternion

from ros_tools.geometry import set_yaw, yaw_from_quaternion, yaw_of


@dataclass
class Fields:
    """Anything with x, y, z, w serves, not only the message class."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    w: float = 1.0


@pytest.mark.parametrize("yaw", [0.0, 0.6, -2.5, math.pi - 1e-9, -math.pi / 2])
def test_set_yaw_then_yaw_of_gives_the_yaw_back(yaw: float) -> None:
    q = Quaternion()
    set_yaw(q, yaw)
    assert (q.x, q.y) == (0.0, 0.0)
    assert (q.z, q.w) == (math.sin(yaw / 2.0), math.cos(yaw / 2.0))
    assert yaw_of(q) == pytest.approx(yaw, abs=1e-12)


def test_set_yaw_overwrites_a_tilted_orientation() -> None:
    """A reused message keeps no roll or pitch from before: the result is a pure rotation about +z."""
    q = Fields(0.3, -0.2, 0.1, 0.9)
    set_yaw(q, 1.0)
    assert (q.x, q.y) == (0.0, 0.0)
    assert yaw_of(q) == pytest.approx(1.0)


def test_yaw_from_quaternion_of_known_rotations() -> None:
    assert yaw_from_quaternion(0.0, 0.0, math.sin(0.6), math.cos(0.6)) == pytest.approx(1.2)
    assert yaw_from_quaternion(0.0, 0.0, 1.0, 0.0) == pytest.approx(math.pi)  # half a turn
    assert yaw_from_quaternion(0.0, 0.0, 0.0, 1.0) == 0.0
    # Roll about x does not change the heading: the x axis still points along +x.
    assert yaw_from_quaternion(math.sin(0.4), 0.0, 0.0, math.cos(0.4)) == pytest.approx(0.0)
    assert yaw_of(Fields(0.0, 0.0, math.sin(-0.3), math.cos(-0.3))) == pytest.approx(-0.6)
