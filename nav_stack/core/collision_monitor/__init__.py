"""Nav2 Jazzy's collision monitor without ROS: zones around the robot, sensor points in the base
frame, and the decision that slows or stops each velocity command (nav2_collision_monitor).

``params`` holds the parameter dataclasses, ``shapes`` the zones (polygon, circle), ``sources`` the
sensor data → base-frame points, ``approach`` the forward simulation of the approach model and
``monitor`` the decision per command and the stop publication rule.
"""

from nav_stack.core.collision_monitor.approach import NO_COLLISION, collision_time
from nav_stack.core.collision_monitor.monitor import (
    INVALID_SOURCE,
    ZERO,
    Action,
    CollisionMonitor,
    Outcome,
    Velocity,
    decide,
)
from nav_stack.core.collision_monitor.params import (
    ActionType,
    CollisionMonitorParams,
    PolygonParams,
    SourceParams,
    parse_points,
)
from nav_stack.core.collision_monitor.shapes import Zone
from nav_stack.core.collision_monitor.sources import (
    Rigid,
    rigid_from_quaternion,
    scan_points,
    shift_corrected,
    source_valid,
    within_height,
)

__all__ = [
    "INVALID_SOURCE",
    "NO_COLLISION",
    "ZERO",
    "Action",
    "ActionType",
    "CollisionMonitor",
    "CollisionMonitorParams",
    "Outcome",
    "PolygonParams",
    "Rigid",
    "SourceParams",
    "Velocity",
    "Zone",
    "collision_time",
    "decide",
    "parse_points",
    "rigid_from_quaternion",
    "scan_points",
    "shift_corrected",
    "source_valid",
    "within_height",
]
