"""QoS profiles of the Nav2 Jazzy ROS surface, in one place (reference: nav2.md §2)."""

from __future__ import annotations

from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)

#: /map, /amcl_pose, costmaps, selectors: late joiners get the last message.
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL, history=HistoryPolicy.KEEP_LAST)
#: /scan as AMCL and the obstacle layer subscribe to it (a reliable publisher satisfies it).
SENSOR = qos_profile_sensor_data
#: /particle_cloud: best effort like Nav2 (RViz must subscribe Best Effort).
PARTICLE_CLOUD = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT,
                            durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
#: Commands and ordinary topics (/cmd_vel, /plan, /initialpose, /goal_pose).
DEFAULT = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
