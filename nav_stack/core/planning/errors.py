"""Planner outcomes with the Jazzy ComputePathToPose / ComputePathThroughPoses error codes.

Planners raise :class:`PlanningError` (code + human message) from deep inside a search; the
planner server core catches it and returns a :class:`PlanResult`, so a node only copies
``error_code``/``error_msg`` into the action result and never handles exceptions itself.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt


class PlanErrorCode(enum.IntEnum):
    """nav2_msgs/action/ComputePathToPose result codes (Jazzy)."""

    NONE = 0
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208


class ThroughPosesErrorCode(enum.IntEnum):
    """nav2_msgs/action/ComputePathThroughPoses result codes (Jazzy): the 20x codes shifted to 30x."""

    NONE = 0
    UNKNOWN = 300
    INVALID_PLANNER = 301
    TF_ERROR = 302
    START_OUTSIDE_MAP = 303
    GOAL_OUTSIDE_MAP = 304
    START_OCCUPIED = 305
    GOAL_OCCUPIED = 306
    TIMEOUT = 307
    NO_VALID_PATH = 308
    NO_VIAPOINTS_GIVEN = 309

    @classmethod
    def from_plan_code(cls, code: PlanErrorCode) -> ThroughPosesErrorCode:
        """The through-poses code matching a single-leg code (NONE stays NONE)."""
        return cls.NONE if code == PlanErrorCode.NONE else cls(int(code) + 100)


class PlanningCancelled(Exception):  # noqa: N818 - named like nav2_core::PlannerCancelled
    """The goal being planned for was cancelled: the search stopped where it was, with no path."""


class PlanningError(Exception):
    """A planning failure carrying its ComputePathToPose code and a message for humans."""

    def __init__(self, code: PlanErrorCode, message: str) -> None:
        super().__init__(f"{code.name}: {message}")
        self.code = code
        self.message = message


@dataclass(frozen=True)
class PlanResult:
    """What a ComputePathTo/ThroughPoses action returns, ROS-free.

    Attributes:
        path: (N, 3) poses ``(x, y, yaw)`` in the costmap frame; empty (0, 3) on failure.
        error_code: ``PlanErrorCode`` or ``ThroughPosesErrorCode`` value (0 = success).
        error_msg: empty on success, otherwise why planning failed.
        planning_time: wall time spent planning (s).
        cancelled: the goal was cancelled while its plan was searched; no path, no error code.
    """

    path: npt.NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))
    error_code: int = 0
    error_msg: str = ""
    planning_time: float = 0.0
    cancelled: bool = False

    @property
    def ok(self) -> bool:
        return self.error_code == 0 and not self.cancelled
