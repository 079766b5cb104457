"""The TF listener clears its buffer on a clock reset, and only then.

A link whose stamps go back by more than BACKWARD_JUMP_S is a clock that jumped back (a simulation
reset). A stamp older than another link's newest is not: AMCL stamps map -> odom transform_tolerance
(1 s) ahead, and comparing odometry against it once dropped the map frame mid-patrol
(bench_dock_patrol, 2026-11-29: "frame [map] does not exist", TF_ERROR 102).
"""

from __future__ import annotations

from typing import Any

import pytest
from builtin_interfaces.msg import Time as TimeMsg
from rclpy.node import Node
from tf2_msgs.msg import TFMessage

from ros_tools.tf.ros import TransformListener, transform_to_msg
from ros_tools.tf.transform import Transform

pytestmark = pytest.mark.ros


def _tf(parent: str, child: str, stamp_s: float) -> TFMessage:
    sec = int(stamp_s)
    stamp = TimeMsg(sec=sec, nanosec=round((stamp_s - sec) * 1e9))
    identity = Transform.from_xy_yaw(0.0, 0.0, 0.0)
    return TFMessage(transforms=[transform_to_msg(identity, parent, child, stamp)])


def test_an_older_stamp_on_another_link_keeps_the_buffer_and_a_reset_clears_it(ros_context: Any) -> None:
    node = Node("tf_reset_probe", context=ros_context)
    listener = TransformListener(node)
    try:
        listener._on_tf(_tf("odom", "base_link", 10.0))
        listener._on_tf(_tf("map", "odom", 11.0))           # AMCL: a scan at 10.0 s, 1 s tolerance
        listener._on_tf(_tf("odom", "base_link", 9.9))      # a late odometry message
        assert listener.buffer.frames() == {"odom": "map", "base_link": "odom"}
        listener._on_tf(_tf("odom", "base_link", 0.1))      # the simulation started again
        assert listener.buffer.frames() == {"base_link": "odom"}  # only the new timeline's link
    finally:
        listener.destroy()
        node.destroy_node()
