"""What the slam node takes in: its ROS-side parameters, a TF listener that wakes a waiting scan,
and the one scan that waits for its odometry (see nav_stack/ros/slam/slam_node.py for how they are used).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from rclpy.node import Node
from sensor_msgs.msg import LaserScan as LaserScanMsg
from tf2_msgs.msg import TFMessage

from ros_tools.tf.ros import TransformListener

MODES = ("mapping", "localization")  # slam_toolbox's ``mode`` values


@dataclass(frozen=True)
class SlamNodeParams:
    """ROS-side knobs, slam_toolbox names (frames, topic) and defaults unless noted.

    Attributes:
        odom_frame / map_frame / base_frame: TF frames (base_footprint: the frame sim2d's odometry moves).
        scan_topic: LaserScan topic.
        transform_timeout: map → odom is stamped this far (s) into the future, AMCL's transform_tolerance.
        transform_publish_period: period (s of the node clock) of the map → odom re-publication
            (0 disables it).
        mode: ``mapping`` or ``localization`` (on the graph in ``map_file_name``; see slam_node.py).
        map_file_name: saved pose graph (serialize_map's ``filename``: path without extension) to
            continue or localize on at configure; empty: start a new map.
        map_start_at_dock: with ``map_file_name``, the robot starts at the graph's first node
            instead of at ``map_start_pose``.
    """

    odom_frame: str = "odom"
    map_frame: str = "map"
    base_frame: str = "base_footprint"
    scan_topic: str = "/scan"
    transform_timeout: float = 0.2
    transform_publish_period: float = 0.05
    mode: str = "mapping"
    map_file_name: str = ""
    map_start_at_dock: bool = False

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"SlamNodeParams.mode must be one of {', '.join(MODES)}, got {self.mode!r}")
        if self.mode == "localization" and not self.map_file_name:
            raise ValueError("SlamNodeParams.mode 'localization' needs map_file_name (a saved pose graph)")
        for name in ("transform_timeout", "transform_publish_period"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"SlamNodeParams.{name} must be a finite number >= 0, got {value}")



class NotifyingListener(TransformListener):
    """A TransformListener that calls ``on_update`` after each /tf or /tf_static message is stored.

    Why: a scan waiting for its odometry is retried exactly when the buffer may have it, in message
    order, instead of by polling. (ros_tools' listener has no public hook for this yet.)
    """

    def __init__(self, node: Node, on_update: Callable[[], None]) -> None:
        self._on_update = on_update  # set first: the subscriptions may deliver during __init__
        super().__init__(node)

    def _on_tf(self, msg: TFMessage) -> None:
        super()._on_tf(msg)
        self._on_update()

    def _on_tf_static(self, msg: TFMessage) -> None:
        super()._on_tf_static(msg)
        self._on_update()


@dataclass
class PendingScan:
    """A scan waiting for the odometry at its stamp; ``received`` is the node clock (s) on arrival."""

    msg: LaserScanMsg
    received: float
