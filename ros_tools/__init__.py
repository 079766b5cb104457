"""ros_tools: what a ROS 2 installation gives its users and a pip install does not.

A pip-installed ROS 2 Jazzy has rclpy and the message packages but no ``ros2`` command, no tf2_ros,
no rosbag2, no RViz and no ``ros2 launch``. This package fills those gaps, in two layers:

* the runtime every package may use: ``runtime`` (the shared process runner, executors, sim-time
  timers, lockstep, action helpers), ``dds`` (DDS stays on this machine), ``tf`` (a transform buffer
  with tf2's semantics), ``launch`` (a process supervisor), geometry, message conversion and console
  helpers;
* the tools that sit above the stacks: ``scenarios`` (the farm), ``viewer`` (the live web viewer),
  ``bag`` and ``report`` (MCAP recording, playback and run reports) and ``cli`` (the ``ros2py``
  command).

Import contracts (pyproject.toml) keep the layers apart: the runtime never imports a tool, sim2d,
nav_stack and smacc_py's library import no tool (only the demos record and report), and the tools
stand apart from one another except the farm, which records and reports its runs. ros_tools never
imports sim2d, nav_stack or smacc_py: it works against any ROS 2 graph, while their ``ros/`` layers
may import it, as Nav2 and SMACC2 both import tf2_ros.
"""
