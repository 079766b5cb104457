"""Recovery behaviors as pure state machines (spin, back up, drive on heading, wait, assisted teleop)."""

from nav_stack.core.behaviors.assisted_teleop import (
    AssistedTeleop,
    AssistedTeleopErrorCode,
    AssistedTeleopParams,
    TeleopCommand,
    teleop_scale,
)
from nav_stack.core.behaviors.base import (
    BackUpErrorCode,
    BehaviorParams,
    BehaviorResult,
    CollisionLookahead,
    DriveOnHeadingErrorCode,
    SpinErrorCode,
)
from nav_stack.core.behaviors.drive import BackUp, DriveGoal, DriveOnHeading
from nav_stack.core.behaviors.spin import Spin, SpinGoal, spin_speed
from nav_stack.core.behaviors.wait import Wait

__all__ = [
    "AssistedTeleop",
    "AssistedTeleopErrorCode",
    "AssistedTeleopParams",
    "BackUp",
    "BackUpErrorCode",
    "BehaviorParams",
    "BehaviorResult",
    "CollisionLookahead",
    "DriveGoal",
    "DriveOnHeading",
    "DriveOnHeadingErrorCode",
    "Spin",
    "SpinErrorCode",
    "SpinGoal",
    "TeleopCommand",
    "Wait",
    "spin_speed",
    "teleop_scale",
]
