"""ROS 2 layer: nodes that translate messages, declare parameters and schedule the core's work.

Importing this package makes DDS discovery stay on this machine unless the user chose a range
(ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET spans machines; see the README).
"""

import os

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
