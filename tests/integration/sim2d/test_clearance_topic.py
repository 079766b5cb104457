"""sim2d's /sim2d/clearance over rclpy: published with each ground-truth pose, and a box dropped in
front of the waffle at its spawn (-2.0, -0.5, 0) sets it to the gap worked out by hand."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

from std_msgs.msg import Float64
from visualization_msgs.msg import Marker

from tests.integration.sim2d.test_sim_node import DEEP, Rig, _rig

pytestmark = pytest.mark.ros

FRONT = 0.069  # m: the waffle's footprint reaches this far ahead of base_footprint


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    for built in _rig(ros_context):
        received = built.received["/sim2d/clearance"]
        built.probe.create_subscription(Float64, "/sim2d/clearance", received.append, DEEP)
        yield built


def test_the_clearance_comes_with_each_pose_and_sees_a_dropped_box(rig: Rig) -> None:
    rig.spin_until(lambda: len(rig.received["/sim2d/clearance"]) >= 5, "clearance messages")
    before = rig.last("/sim2d/clearance").data
    assert 0.05 < before < 2.0  # the robot stands free in turtlebot3_world
    marker = Marker(type=Marker.CYLINDER, action=Marker.ADD)
    marker.header.frame_id = "map"
    marker.pose.position.x, marker.pose.position.y = -1.7, -0.5  # its near side 0.131 m ahead of the body
    marker.scale.x = marker.scale.y = 0.2
    rig.send("/sim2d/spawn_obstacle", marker)
    expected = -1.7 - 0.1 - (-2.0 + FRONT)
    rig.spin_until(lambda: rig.last("/sim2d/clearance").data == pytest.approx(expected, abs=1e-6),
                   "the clearance to the dropped box")
    assert expected < before
    # one clearance per ground-truth pose (both at the odometry rate, from the same step)
    rig.wait_sim(0.5)
    counts = len(rig.received["/sim2d/clearance"]), len(rig.received["/ground_truth"])
    assert abs(counts[0] - counts[1]) <= 1, counts
