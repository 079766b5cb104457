"""Recording and replaying ROS 2 topics as MCAP files that ``ros2 bag`` and Foxglove open.

pip-installed ROS 2 has no rosbag2. This package records with rclpy raw subscriptions into the
MCAP ``ros2`` profile (CDR messages, ``ros2msg`` schemas assembled from the installed ``.msg``
files, the publishers' QoS with every channel), prints ``info`` like ``ros2 bag info`` and plays
recordings back with their timing, QoS and optionally ``/clock``. Command: ``navsuite-bag``
(:mod:`navsuite_tools.bag.main`); run reports are in :mod:`navsuite_tools.report`.
"""

from navsuite_tools.bag.reader import BagError, BagMessage, BagReader, TopicInfo
from navsuite_tools.bag.schema import message_definition
from navsuite_tools.bag.writer import BagWriter

__all__ = ["BagError", "BagMessage", "BagReader", "BagWriter", "TopicInfo", "message_definition"]
