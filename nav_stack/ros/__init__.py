"""ROS 2 layer: nodes that translate messages, declare parameters and schedule the core's work.

Importing this package gives the process the suite's DDS settings unless the user chose their own
(ros_tools.dds: discovery stays on this machine; ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET spans
machines, see the README).
"""

from ros_tools.dds import keep_dds_local

keep_dds_local()
