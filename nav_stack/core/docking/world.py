"""What the docking sequences need from the world, and what they hand back each tick.

The sequences are pure: time comes as ``now`` (s, node clock), and poses, detections and the costmap
come through :class:`DockingWorld`, which the node implements with TF and subscriptions and a test
implements with a kinematic robot. A tick returns a :class:`DockingStep`: the command to publish, a
staging navigation to start or cancel, the feedback state, and at the end the :class:`DockingResult`.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Protocol

from nav_stack.core.control.base import Twist2D
from nav_stack.core.docking.controller import Obstacles
from nav_stack.core.docking.errors import DockErrorCode, DockingState, FrameUnavailable
from nav_stack.core.docking.simple_charging_dock import Detection
from nav_stack.core.docking.spatial import Pose3D
from nav_stack.core.geometry import Pose2D

STOP = Twist2D(0.0, 0.0)


class DockingWorld(Protocol):
    """Poses through TF and the local costmap. Lookups raise FrameUnavailable with the reason."""

    def robot_pose(self, frame: str) -> Pose2D:
        """The latest robot base pose in ``frame``."""
        ...

    def transform(self, pose: Pose2D, source: str, target: str) -> Pose2D:
        """``pose`` (in ``source``) expressed in ``target``, with the latest transform."""
        ...

    def detection_in(self, detection: Detection, frame: str) -> Pose3D:
        """A detection expressed in ``frame``, with the transform at its stamp."""
        ...

    def obstacles(self) -> Obstacles | None:
        """The local costmap and footprint; None while none was received."""
        ...


def robot_or_none(world: DockingWorld, frame: str) -> Pose2D | None:
    """The robot pose in ``frame``, or None when unknown (a plugin then answers "not docked")."""
    if not frame:
        return None
    try:
        return world.robot_pose(frame)
    except FrameUnavailable:
        return None


def robot_in_costmap(world: DockingWorld, robot: Pose2D, frame: str, obstacles: Obstacles | None) -> Pose2D:
    """The robot pose in the costmap's frame, given its pose ``robot`` in ``frame``."""
    if obstacles is None or obstacles.frame == frame:
        return robot
    return world.robot_pose(obstacles.frame)


class DockingOutcome(enum.Enum):
    SUCCEEDED = "succeeded"
    ABORTED = "aborted"
    CANCELED = "canceled"


@dataclass(frozen=True)
class DockingResult:
    """How a dock or undock goal ended; ``dock_type``: the plugin docked to (for a later undock)."""

    outcome: DockingOutcome
    error_code: DockErrorCode = DockErrorCode.NONE
    error_msg: str = ""
    num_retries: int = 0
    dock_type: str = ""

    @property
    def success(self) -> bool:
        return self.outcome is DockingOutcome.SUCCEEDED


@dataclass(frozen=True)
class StagingGoal:
    """Navigate to ``pose`` in ``frame`` (NavigateToPose) within ``time_left`` s; ``attempt`` 1 or 2."""

    pose: Pose2D
    frame: str
    attempt: int
    time_left: float


@dataclass(frozen=True)
class DockingStep:
    """One tick's output. ``command``: publish it (None: publish nothing this tick)."""

    state: DockingState
    num_retries: int = 0
    command: Twist2D | None = None
    navigate: StagingGoal | None = None
    cancel_navigation: bool = False
    result: DockingResult | None = None
