"""Command-line tools ROS users expect (``ros2 topic|node|service|action|param|interface``).

A pip-installed ROS 2 Jazzy has rclpy and the message packages but no ``ros2`` command, no
ros2cli and no rosidl_runtime_py. This package fills that gap with the ``ros2py`` command, built
only on rclpy's graph and parameter APIs, ``importlib`` for interface types and a small
message ↔ dict/YAML converter of its own (:mod:`ros_tools.convert`).

It depends on rclpy, message packages, the standard library and PyYAML only. It never imports
sim2d, nav_stack or smacc_py: it is a generic ROS tool that works against any ROS 2 graph.
"""
