"""One FollowPath goal's control cycle as a pure decision: what controller_server does next.

Why here and not in the node: the order of the cycle's checks is the controller server's behaviour
(Nav2's ``computeAndPublishVelocity``): a costmap with no data holds the robot and, past
``costmap_update_timeout``, fails; a reached goal succeeds; no progress fails; then the controller
computes a command, and a controller that finds none is tolerated for ``failure_tolerance`` s. Kept
in the node, none of that could be tested without rclpy; here each rule has a unit test
(tests/unit/nav_stack/test_follow_path.py) and the node only looks up poses, applies the decision
and publishes.

Times are the node clock's seconds (sim time under a simulator): ``now`` is the cycle's slot on
the timer's grid, so the tolerances count control periods, not the executor's lateness.

A new goal that preempts a running one takes over its state as far as the new path allows
(:meth:`PathFollowing.take_over`): another controller starts everything afresh; the same controller
keeps its state and the goal checker restarts (Nav2's setPlan); and a path that is only the rest of
the current one toward the same goal (the bt_navigator's 1 Hz replan, :func:`is_remainder`) swaps
the path array and keeps every plugin's state, including the goal checker's latch.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_stack.core.control.base import ControllerErrorCode, CostGrid, NoValidControl, Twist2D
from nav_stack.core.control.checkers import FINAL_TURN_PROGRESS
from nav_stack.core.control.path_handler import PathHandler
from nav_stack.core.geometry import FloatArray, Pose2D, angle_diff, nearest_index

STOP = Twist2D(0.0, 0.0)
#: m, rad: how close two paths' last poses must be to be the same goal
SAME_END_XY, SAME_END_YAW = 1e-3, 1e-3
#: (dx, dy) of a cell and its eight neighbours
_NEIGHBOURS = np.array([(dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)], dtype=np.int64)


class Action(enum.Enum):
    """What the node does with a cycle's decision."""

    HOLD = "hold"          # publish a zero command, the goal goes on (no costmap data yet)
    DRIVE = "drive"        # publish ``cmd`` and the feedback
    SUCCEED = "succeed"    # the goal is reached: stop, SUCCEEDED
    ABORT = "abort"        # stop, ABORTED with ``code`` and ``message``


class Takeover(enum.Enum):
    """What a new goal kept of the goal it preempted (:meth:`PathFollowing.take_over`)."""

    FRESH = "fresh"            # nothing ran, or another controller: every plugin starts over
    NEW_PATH = "new path"      # same controller, another path: the goal checker starts over
    REMAINDER = "remainder"    # the rest of the same path: only the path array changed


def _cells(points: FloatArray, size: float) -> FloatArray:
    """One int64 key per point: its cell in a grid of ``size`` m squares (x in the high 32 bits)."""
    ix = np.floor(points[:, 0] / size).astype(np.int64)
    iy = np.floor(points[:, 1] / size).astype(np.int64)
    return np.asarray((ix << 32) + iy, dtype=np.int64)


def _near(points: FloatArray, others: FloatArray, size: float) -> bool:
    """Whether every point lies in the cell of one of ``others`` or in one of its eight neighbours."""
    grown = (_cells(others, size)[:, None] + ((_NEIGHBOURS[:, 0] << 32) + _NEIGHBOURS[:, 1])[None, :]).ravel()
    return bool(np.isin(_cells(points, size), grown).all())


def is_remainder(current: FloatArray, new: FloatArray, tolerance: float) -> bool:
    """Whether ``new`` is what is left of ``current``: the same last pose (within 1 mm and 1 mrad) and,
    from the pose of ``current`` nearest ``new``'s first (where the robot was when it was planned),
    the same cells: in a grid of ``tolerance`` m squares every pose of either path lies in the cell
    of a pose of the other or next to it, so no pose is 2.9 ``tolerance`` or more from the other path,
    and poses within ``tolerance`` of each other always match.

    Why: the bt_navigator replans every second and sends each plan as a new FollowPath goal; on an
    unchanged map the plan is the same route from where the robot now is, and the controller need
    not treat it as a new goal. Both paths are (N, 3) arrays in the same frame; a non-positive
    tolerance never matches. O(N log N), about a millisecond for a thousand poses.
    """
    if tolerance <= 0.0 or len(current) == 0 or len(new) == 0:
        return False
    end, new_end = current[-1], new[-1]
    if (math.hypot(end[0] - new_end[0], end[1] - new_end[1]) > SAME_END_XY
            or abs(angle_diff(float(end[2]), float(new_end[2]))) > SAME_END_YAW):
        return False
    ahead = current[nearest_index(current, float(new[0, 0]), float(new[0, 1])):]
    return _near(new, ahead, tolerance) and _near(ahead, new, tolerance)


@dataclass(frozen=True)
class Decision:
    """A cycle's outcome. ``distance_to_goal`` (m along the path) is set with DRIVE."""

    action: Action
    cmd: Twist2D = STOP
    code: int = ControllerErrorCode.NONE
    message: str = ""
    distance_to_goal: float = 0.0


@dataclass(frozen=True)
class Plugins:
    """The goal's plugins: a LocalController, a goal checker and a progress checker."""

    controller: Any
    goal_checker: Any
    progress_checker: Any


@dataclass(frozen=True)
class CycleInputs:
    """What one cycle sees (poses in m and rad).

    Attributes:
        now: the cycle's time (s).
        robot: the robot in the path's frame.
        robot_local: the robot in the local costmap's frame.
        path_in_local: the path frame's origin in the local costmap's frame.
        velocity: the robot's velocity from odometry (m/s, rad/s).
        grid: the local costmap.
    """

    now: float
    robot: Pose2D
    robot_local: Pose2D
    path_in_local: Pose2D
    velocity: Twist2D
    grid: CostGrid


class PathFollowing:
    """The state of one FollowPath goal between cycles, and its decisions.

    Args:
        ids: (controller, goal checker, progress checker) ids of the goal.
        path: the path, (N, 3) x, y, yaw in its frame.
    """

    def __init__(self, ids: tuple[str, str, str], path: FloatArray) -> None:
        self.ids = ids
        self.handler = PathHandler()
        self.handler.set_plan(path)
        self.last_valid = -math.inf  # s: the last cycle with a valid command (or the goal's first)
        self.turning_at_goal = False  # the goal's xy is reached: only the final rotation remains

    def take_over(self, previous: PathFollowing | None, plugins: Plugins, tolerance: float) -> Takeover:
        """Start this goal from the state of the goal it preempts (None: none ran) and reset the
        plugins that must start over; ``plugins`` are this goal's, ``tolerance`` (m) is
        :func:`is_remainder`'s.

        Another controller (or no goal) resets every plugin. The same controller keeps its state and
        this goal keeps the time of the last valid command (no stop, no fresh patience), as Nav2's
        controller server does on a preemption; a progress checker of another id starts over, and
        so does the goal checker unless the path is the rest of the current one toward the same goal.
        """
        if previous is None or previous.ids[0] != self.ids[0]:
            for plugin in (plugins.controller, plugins.goal_checker, plugins.progress_checker):
                plugin.reset()
            return Takeover.FRESH
        self.continue_from(previous)
        if previous.ids[2] != self.ids[2]:
            plugins.progress_checker.reset()
        same_checker = previous.ids[1] == self.ids[1]
        if same_checker and is_remainder(previous.handler.plan, self.handler.plan, tolerance):
            self.turning_at_goal = previous.turning_at_goal
            return Takeover.REMAINDER
        plugins.goal_checker.reset()
        return Takeover.NEW_PATH

    def continue_from(self, previous: PathFollowing) -> None:
        """Take over a preempted goal's timing: the time of its last valid command (no fresh patience)."""
        self.last_valid = previous.last_valid

    def _start(self, now: float) -> None:
        if self.last_valid == -math.inf:
            self.last_valid = now

    def without_costmap(self, now: float, never_had_data: bool, costmap_update_timeout: float) -> Decision:
        """The cycle when the local costmap has no data, or none since it was cleared: hold (never drive
        on a grid that may lack the obstacles around the robot), and fail after the timeout (s)."""
        self._start(now)
        if now - self.last_valid > costmap_update_timeout:
            why = ("the local costmap has no data (no scan or no robot pose)" if never_had_data
                   else "the local costmap has had no scan since it was cleared")
            return Decision(Action.ABORT, code=ControllerErrorCode.UNKNOWN, message=why)
        return Decision(Action.HOLD)

    def step(self, cycle: CycleInputs, plugins: Plugins, failure_tolerance: float,
             stillness_note: Callable[[], str] = lambda: "") -> Decision:
        """The cycle with a current costmap: goal reached, progress, then the controller's command.

        Args:
            failure_tolerance: s without a valid command before PATIENCE_EXCEEDED; 0 fails at once
                with the controller's own code (NO_VALID_CONTROL); -1 never gives up.
            stillness_note: text appended to a no-progress message (why the robot did not move).

        Raises:
            ControllerError: from the controller (other than a tolerated NoValidControl).
        """
        self._start(cycle.now)
        checker, progress = plugins.goal_checker, plugins.progress_checker
        if checker.is_goal_reached(cycle.robot, self.handler.goal, cycle.velocity):
            return Decision(Action.SUCCEED)
        if checker.xy_reached and not self.turning_at_goal:
            self.turning_at_goal = True
            progress.reset()  # the final rotation gets a fresh window, in which turning is progress
        if not progress.check(cycle.robot, cycle.now, turning=self.turning_at_goal):
            radius = progress.params.required_movement_radius
            moved = (f"turned less than {FINAL_TURN_PROGRESS} rad toward the goal heading"
                     if self.turning_at_goal else f"moved less than {radius} m")
            return Decision(Action.ABORT, code=ControllerErrorCode.FAILED_TO_MAKE_PROGRESS,
                            message=f"the robot {moved} in {progress.params.movement_time_allowance} s"
                                    + stillness_note())
        local_path = self.handler.local_path(cycle.robot, cycle.path_in_local, cycle.grid)
        try:
            cmd = plugins.controller.compute_velocity(cycle.robot_local, cycle.velocity, local_path,
                                                      cycle.grid)
            self.last_valid = cycle.now
        except NoValidControl as error:
            if failure_tolerance == 0.0:
                return Decision(Action.ABORT, code=error.code, message=error.message)
            if failure_tolerance != -1.0 and cycle.now - self.last_valid > failure_tolerance:
                return Decision(Action.ABORT, code=ControllerErrorCode.PATIENCE_EXCEEDED,
                                message=f"no valid command for {failure_tolerance} s: {error.message}")
            cmd = STOP
        return Decision(Action.DRIVE, cmd, distance_to_goal=float(self.handler.distance_to_goal(cycle.robot)))
