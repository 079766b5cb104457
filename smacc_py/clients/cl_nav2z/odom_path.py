"""The odometry tracker's bookkeeping (pure Python): record a path, clear it while driving back.

SMACC2's CpOdomTracker keeps a stack of paths: each motion pushes a new one; in RECORD_PATH mode a
pose is appended when the robot moved more than ``record_point_distance_threshold`` m or turned more
than ``record_angular_distance_threshold`` rad since the last recorded pose; in CLEAR_PATH mode the
last recorded pose is removed once the robot is back within ``clear_point_distance_threshold`` m of it
(the path is consumed while undoing it). Poses are (x, y, yaw) in the odom frame.
"""

from __future__ import annotations

import enum
import math
import threading
from dataclasses import dataclass

from smacc_py.clients.cl_nav2z.geometry import Pose2D, normalize_angle


class WorkingMode(enum.Enum):
    """What the tracker does with each odometry message."""

    RECORD_PATH = "record_path"
    CLEAR_PATH = "clear_path"
    IDLE = "idle"


@dataclass(frozen=True)
class OdomTrackerParams:
    """Thresholds (SMACC2 names; m and rad)."""

    record_point_distance_threshold: float = 0.005
    record_angular_distance_threshold: float = 0.1
    clear_point_distance_threshold: float = 0.05
    clear_angular_distance_threshold: float = 0.1

    def __post_init__(self) -> None:
        for name in (
            "record_point_distance_threshold",
            "record_angular_distance_threshold",
            "clear_point_distance_threshold",
            "clear_angular_distance_threshold",
        ):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"OdomTrackerParams.{name} must be > 0, got {getattr(self, name)!r}")


class OdomPath:
    """Thread-safe stack of recorded paths; the top one is the working path."""

    def __init__(self, params: OdomTrackerParams | None = None) -> None:
        self.params = params or OdomTrackerParams()
        self.mode = WorkingMode.IDLE
        self._lock = threading.Lock()
        self._stack: list[tuple[str, list[Pose2D]]] = [("", [])]

    def feed(self, pose: Pose2D) -> bool:
        """Process one odometry pose in the current mode; True when the working path changed."""
        p = self.params
        with self._lock:
            path = self._stack[-1][1]
            if self.mode is WorkingMode.RECORD_PATH:
                if path:
                    last = path[-1]
                    moved = math.hypot(pose[0] - last[0], pose[1] - last[1])
                    turned = abs(normalize_angle(pose[2] - last[2]))
                    if (
                        moved <= p.record_point_distance_threshold
                        and turned <= p.record_angular_distance_threshold
                    ):
                        return False
                path.append(pose)
                return True
            if self.mode is WorkingMode.CLEAR_PATH and path:
                changed = False
                while (
                    path
                    and math.hypot(pose[0] - path[-1][0], pose[1] - path[-1][1])
                    <= p.clear_point_distance_threshold
                ):
                    path.pop()
                    changed = True
                return changed
            return False

    def set_mode(self, mode: WorkingMode) -> None:
        """Switch RECORD_PATH / CLEAR_PATH / IDLE."""
        self.mode = mode

    def push_path(self, name: str = "") -> None:
        """Start a new working path (the previous one stays on the stack)."""
        with self._lock:
            self._stack.append((name, []))

    def pop_path(self) -> list[Pose2D]:
        """Remove and return the working path (the bottom path is emptied, never removed)."""
        with self._lock:
            if len(self._stack) == 1:
                path = self._stack[0][1]
                self._stack[0] = ("", [])
                return path
            return self._stack.pop()[1]

    def clear_path(self) -> None:
        """Empty the working path."""
        with self._lock:
            self._stack[-1][1].clear()

    def path(self) -> list[Pose2D]:
        """A copy of the working path."""
        with self._lock:
            return list(self._stack[-1][1])

    def stacked_path(self) -> list[Pose2D]:
        """Every path of the stack, bottom first, concatenated."""
        with self._lock:
            return [pose for _, path in self._stack for pose in path]
