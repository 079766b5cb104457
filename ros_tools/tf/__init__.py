"""Transforms without tf2_ros: a buffer with tf2's lookup semantics and /tf, /tf_static plumbing.

``transform`` and ``buffer`` are plain Python (unit-tested without ROS); ``ros`` holds the
listener and broadcasters. Import the ROS parts from ``ros_tools.tf.ros``.
"""

from ros_tools.tf.buffer import ConnectivityError, ExtrapolationError, TransformBuffer, TransformError
from ros_tools.tf.transform import Transform, interpolate

__all__ = ["ConnectivityError", "ExtrapolationError", "Transform", "TransformBuffer", "TransformError",
           "interpolate"]
