"""The smoother server's logic without ROS: plugin selection, input checks, error codes, timing.

A smoother_server node builds one :class:`SmootherServerCore` at configure time from its
``smoother_plugins`` and hands it every SmoothPath goal (the path already in the costmap's frame),
then copies the :class:`SmoothResult` into the action result. No exception escapes
:meth:`SmootherServerCore.smooth_path`.

As Nav2's server does: the smoother id is resolved first (an empty id picks the only plugin when
there is one), then the path is checked, smoothed, and with ``check_for_collisions`` the footprint
is placed at every smoothed pose; the first pose in collision makes the goal fail with
SMOOTHED_PATH_IN_COLLISION, the smoothed path still in the result. A smoother that runs out of time
gives TIMEOUT with ``was_completed`` false. Nav2 does not check poses for NaN; here a non-finite
position or an orientation that cannot be normalised is INVALID_PATH with the pose's index, since
NaN would otherwise spread through the whole smoothed path.
"""

from __future__ import annotations

import enum
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from nav_stack.core.control.base import CostGrid, Footprint
from nav_stack.core.geometry import FloatArray
from nav_stack.core.smoothing.collision import first_collision
from nav_stack.core.smoothing.simple_smoother import SimpleSmoother


class SmoothErrorCode(enum.IntEnum):
    """nav2_msgs/action/SmoothPath result codes (Jazzy)."""

    NONE = 0
    UNKNOWN = 500
    INVALID_SMOOTHER = 501
    TIMEOUT = 502
    SMOOTHED_PATH_IN_COLLISION = 503
    FAILED_TO_SMOOTH_PATH = 504
    INVALID_PATH = 505


@dataclass(frozen=True)
class SmoothResult:
    """A SmoothPath outcome: the (N, 3) path, whether smoothing finished, its duration (s), the code.

    ``cancelled``: the goal was cancelled while smoothing (no error code; the node reports CANCELED).
    """

    path: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    was_completed: bool = False
    smoothing_duration: float = 0.0
    error_code: int = SmoothErrorCode.NONE
    error_msg: str = ""
    cancelled: bool = False

    @property
    def ok(self) -> bool:
        return self.error_code == SmoothErrorCode.NONE and not self.cancelled


class SmoothingError(Exception):
    """A refused goal: its SmoothPath code and a message for people."""

    def __init__(self, code: SmoothErrorCode, message: str) -> None:
        super().__init__(f"{code.name}: {message}")
        self.code, self.message = code, message


def check_path(path: FloatArray) -> None:
    """Raise INVALID_PATH for an empty path or a pose that is not finite (NaN yaw: no orientation)."""
    if len(path) == 0:
        raise SmoothingError(SmoothErrorCode.INVALID_PATH, "the path to smooth is empty")
    bad = ~np.isfinite(path[:, :3]).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        x, y = float(path[i, 0]), float(path[i, 1])
        what = (f"position ({x}, {y}) is not finite" if not (math.isfinite(x) and math.isfinite(y))
                else "orientation cannot be normalised (NaN or zero-norm quaternion)")
        raise SmoothingError(SmoothErrorCode.INVALID_PATH, f"pose {i} of the path: {what}")


class SmootherServerCore:
    """Dispatches SmoothPath goals to the smoother plugins by id ("simple_smoother", ...)."""

    def __init__(self, smoothers: Mapping[str, SimpleSmoother],
                 clock: Callable[[], float] = time.monotonic) -> None:
        if not smoothers:
            raise ValueError("the smoother server needs at least one smoother plugin")
        self.smoothers = dict(smoothers)
        self._clock = clock

    def smoother(self, smoother_id: str) -> SimpleSmoother:
        """The plugin named ``smoother_id``; the only one for an empty id; else INVALID_SMOOTHER."""
        if smoother_id == "" and len(self.smoothers) == 1:
            return next(iter(self.smoothers.values()))
        if smoother_id not in self.smoothers:
            raise SmoothingError(SmoothErrorCode.INVALID_SMOOTHER,
                                 f"smoother id '{smoother_id}' is not one of {sorted(self.smoothers)}")
        return self.smoothers[smoother_id]

    def smooth_path(self, path: FloatArray, smoother_id: str, max_duration: float, grid: CostGrid | None,
                    check_for_collisions: bool = False, footprint: Footprint | None = None,
                    should_stop: Callable[[], bool] = lambda: False) -> SmoothResult:
        """Smooth ``path`` (N, 3, grid frame) with plugin ``smoother_id`` in ``max_duration`` s; see the
        module docstring for the order of the checks. ``should_stop`` is polled every sweep (a cancel)."""
        started = self._clock()
        try:
            smoother = self.smoother(smoother_id)
            check_path(path)
            if check_for_collisions and (grid is None or footprint is None):
                raise SmoothingError(SmoothErrorCode.UNKNOWN, "no costmap to check the smoothed path against")
        except SmoothingError as error:
            return SmoothResult(error_code=error.code, error_msg=error.message)
        outcome = smoother.smooth(path, max_duration, grid, should_stop)
        duration = self._clock() - started
        if outcome.timed_out:
            if should_stop():
                return SmoothResult(outcome.path, False, duration, cancelled=True,
                                    error_msg="cancelled while smoothing")
            return SmoothResult(outcome.path, False, duration, SmoothErrorCode.TIMEOUT,
                                f"smoothing took longer than the {max_duration:.3f} s allowed")
        if check_for_collisions:
            assert grid is not None and footprint is not None
            hit = first_collision(footprint, grid, outcome.path)
            if hit is not None:
                x, y, yaw = (float(v) for v in outcome.path[hit])
                return SmoothResult(outcome.path, True, duration, SmoothErrorCode.SMOOTHED_PATH_IN_COLLISION,
                                    f"the smoothed path collides at pose {hit} "
                                    f"(x {x:.3f}, y {y:.3f}, yaw {yaw:.3f})")
        return SmoothResult(outcome.path, True, duration)
