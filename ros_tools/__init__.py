"""ros_tools: what a ROS 2 installation gives its users and a pip install does not.

A pip-installed ROS 2 Jazzy has rclpy and the message packages but no ``ros2`` command, no tf2_ros,
no rosbag2, no RViz and no ``ros2 launch``. This package fills those gaps:

* ``ros_tools.cli``: the ``ros2py`` command (``topic|node|service|action|param|interface``), built on
  rclpy's graph and parameter APIs and the message ↔ dict/YAML converter in :mod:`ros_tools.convert`;
* ``ros_tools.tf``: a transform buffer with tf2's semantics, listener and broadcasters;
* ``ros_tools.launch``: a process supervisor for bringing up several nodes;
* (as they land) a live web viewer, MCAP recording and playback, and run reports.

It never imports sim2d, nav_stack or smacc_py (import-linter checks it): it works against any
ROS 2 graph, while their ``ros/`` layers may import it, as Nav2 and SMACC2 both import tf2_ros.
"""
