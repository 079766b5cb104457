"""The planner server's logic without ROS: plugin selection, input checks, error codes, timing.

A planner_server node builds one :class:`PlannerServerCore` at configure time from its
``planner_plugins`` and for every ComputePathToPose / ComputePathThroughPoses goal passes the
poses (already in the costmap frame) and the current costmap, then copies the
:class:`PlanResult` into the action result. No exception escapes these two methods.

Orientation: a node converts quaternions with :func:`geometry.yaw_or_nan`; a goal whose yaw is
NaN (NaN or zero-norm quaternion) is refused with UNKNOWN (200/300) and a message saying so.
Nav2 has no "invalid goal" code; GOAL_OCCUPIED would send an operator to inspect the costmap
for an obstacle that is not there, while UNKNOWN with an explicit ``error_msg`` tells the truth.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning.common import CostArray, GlobalPlanner, never
from nav_stack.core.planning.errors import (
    PlanErrorCode,
    PlanningCancelled,
    PlanningError,
    PlanResult,
    ThroughPosesErrorCode,
)


def _check_pose(pose: Pose2D, what: str) -> None:
    if not (math.isfinite(pose.x) and math.isfinite(pose.y)):
        raise PlanningError(PlanErrorCode.UNKNOWN, f"{what} position ({pose.x}, {pose.y}) is not finite")
    if not math.isfinite(pose.yaw):
        raise PlanningError(
            PlanErrorCode.UNKNOWN, f"{what} orientation cannot be normalised (NaN or zero-norm quaternion)"
        )


class PlannerServerCore:
    """Dispatches plan requests to planner plugins selected by id ("GridBased", ...)."""

    def __init__(
        self, planners: Mapping[str, GlobalPlanner], clock: Callable[[], float] = time.monotonic
    ) -> None:
        if not planners:
            raise ValueError("planner server needs at least one planner plugin")
        self.planners = dict(planners)
        self._clock = clock

    def _planner(self, planner_id: str) -> GlobalPlanner:
        if planner_id == "" and len(self.planners) == 1:
            return next(iter(self.planners.values()))
        if planner_id not in self.planners:
            raise PlanningError(
                PlanErrorCode.INVALID_PLANNER,
                f"planner id '{planner_id}' is not one of {sorted(self.planners)}",
            )
        return self.planners[planner_id]

    def compute_path_to_pose(
        self, start: Pose2D, goal: Pose2D, planner_id: str, costs: CostArray, spec: GridSpec,
        cancel_checker: Callable[[], bool] = never,
    ) -> PlanResult:
        """One leg; error codes of ComputePathToPose. ``cancel_checker`` is polled during the search:
        once true, the result says ``cancelled`` and carries no path."""
        started = self._clock()
        try:
            path = self._leg(start, goal, planner_id, costs, spec, cancel_checker)
        except PlanningError as err:
            return PlanResult(
                error_code=int(err.code), error_msg=err.message, planning_time=self._clock() - started
            )
        except PlanningCancelled as cancelled:
            return self._cancelled(cancelled, started)
        return PlanResult(path=path, planning_time=self._clock() - started)

    def compute_path_through_poses(
        self, start: Pose2D, goals: Sequence[Pose2D], planner_id: str, costs: CostArray, spec: GridSpec,
        cancel_checker: Callable[[], bool] = never,
    ) -> PlanResult:
        """Legs start→g0→g1…, concatenated without repeating the joints; ComputePathThroughPoses codes."""
        started = self._clock()
        if not goals:
            return PlanResult(
                error_code=int(ThroughPosesErrorCode.NO_VIAPOINTS_GIVEN),
                error_msg="no goals given",
                planning_time=0.0,
            )
        legs = []
        leg_start = start
        try:
            for i, goal in enumerate(goals):
                try:
                    leg = self._leg(leg_start, goal, planner_id, costs, spec, cancel_checker)
                except PlanningError as err:
                    raise PlanningError(
                        err.code, f"leg {i} to ({goal.x:.3f}, {goal.y:.3f}): {err.message}"
                    ) from err
                legs.append(leg if i == 0 else leg[1:])
                leg_start = goal
        except PlanningError as err:
            return PlanResult(
                error_code=int(ThroughPosesErrorCode.from_plan_code(err.code)),
                error_msg=err.message,
                planning_time=self._clock() - started,
            )
        except PlanningCancelled as cancelled:
            return self._cancelled(cancelled, started)
        return PlanResult(path=np.vstack(legs), planning_time=self._clock() - started)

    def _cancelled(self, cancelled: PlanningCancelled, started: float) -> PlanResult:
        """The result of a search stopped by its goal's cancel: no path, no error code."""
        return PlanResult(error_msg=str(cancelled), planning_time=self._clock() - started, cancelled=True)

    def _leg(
        self, start: Pose2D, goal: Pose2D, planner_id: str, costs: CostArray, spec: GridSpec,
        cancel_checker: Callable[[], bool],
    ) -> np.ndarray:
        planner = self._planner(planner_id)
        _check_pose(start, "start")
        _check_pose(goal, "goal")
        try:
            return planner.create_plan(start, goal, costs, spec, cancel_checker)
        except (PlanningError, PlanningCancelled):
            raise
        except Exception as exc:  # a plugin bug must become UNKNOWN, never kill the server
            raise PlanningError(PlanErrorCode.UNKNOWN, f"{type(exc).__name__}: {exc}") from exc
