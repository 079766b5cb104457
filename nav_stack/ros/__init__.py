"""ROS 2 layer: nodes that translate messages, declare parameters and schedule the core's work.

Importing it changes nothing in the process: the suite's DDS settings (ros_tools.dds: discovery stays
on this machine unless the user chose a range) are applied where rclpy is initialised, by the shared
runner (ros_tools.runtime.runner.ros_process).
"""
