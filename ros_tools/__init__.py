"""ros_tools: the runtime a ROS 2 installation gives its users and a pip install does not.

A pip-installed ROS 2 Jazzy has rclpy and the message packages but no tf2_ros, no ``ros2 launch`` and
none of the executor and timer plumbing a simulated, lockstepped stack needs. This package is that
runtime, used by sim2d's, nav_stack's and smacc_py's ``ros/`` layers: ``runtime`` (the shared process
runner, executors, sim-time timers, lockstep, action helpers), ``dds`` (DDS stays on this machine),
``tf`` (a transform buffer with tf2's semantics), ``launch`` (a process supervisor), geometry, message
conversion and console helpers.

The tools above the stacks (the farm, the viewer, bags and reports, the ``ros2py`` command) are
navsuite_tools. Import contracts (pyproject.toml) keep the two apart: ros_tools never imports a tool,
and it never imports sim2d, nav_stack or smacc_py: it works against any ROS 2 graph, as tf2_ros does
for Nav2 and SMACC2.
"""
