"""The UndockRobot sequence of opennav_docking, ticked like :class:`.sequence.DockingSequence`.

1. The plugin comes from the goal's ``dock_type``, else from the last successful docking, else the
   only plugin; none: DOCK_NOT_VALID. A charging dock that reports neither docked nor charging means
   the robot is not in a dock: success at once (as newer Nav2 releases answer).
2. The robot's pose now stands for the dock pose; its staging pose (the plugin's offsets) in
   ``fixed_frame`` is the target.
3. Each tick: past ``max_undocking_time`` → FAILED_TO_CONTROL; within the undock tolerances of the
   staging pose → success if charging stopped (FAILED_TO_CONTROL otherwise); else the control law
   drives there (backwards when docking forwards), FAILED_TO_CONTROL if the motion would collide.
"""

from __future__ import annotations

from dataclasses import dataclass

from nav_stack.core.docking.controller import DockingController
from nav_stack.core.docking.database import DockDatabase
from nav_stack.core.docking.errors import (
    DockErrorCode,
    DockingError,
    DockingState,
    DockNotValid,
    FailedToControl,
    FrameUnavailable,
)
from nav_stack.core.docking.params import DockingServerParams
from nav_stack.core.docking.simple_charging_dock import SimpleChargingDock
from nav_stack.core.docking.world import (
    STOP,
    DockingOutcome,
    DockingResult,
    DockingStep,
    DockingWorld,
    robot_in_costmap,
    robot_or_none,
)
from nav_stack.core.geometry import Pose2D


@dataclass(frozen=True)
class UndockRequest:
    """An UndockRobot goal: the dock type ("" for the docked one) and ``max_undocking_time`` s."""

    dock_type: str = ""
    max_undocking_time: float = 30.0


class UndockingSequence:
    """One UndockRobot goal, ticked until :attr:`result` is set."""

    def __init__(self, request: UndockRequest, docked_type: str, params: DockingServerParams,
                 controller: DockingController, database: DockDatabase[SimpleChargingDock],
                 world: DockingWorld, now: float) -> None:
        self.request, self.docked_type, self.params = request, docked_type, params
        self.controller, self.database, self.world = controller, database, world
        self.start = now
        self.result: DockingResult | None = None
        self.plugin: SimpleChargingDock | None = None
        self.staging: Pose2D | None = None  # in fixed_frame
        self._cancel_requested = False

    def cancel(self) -> None:
        """The goal was cancelled: the next tick stops the robot and ends it CANCELED."""
        self._cancel_requested = True

    def tick(self, now: float) -> DockingStep:
        """Advance by one control period; the step to carry out."""
        if self.result is not None:
            return DockingStep(DockingState.NONE, result=self.result)
        if self._cancel_requested:
            return self._finish(DockingOutcome.CANCELED, DockErrorCode.NONE, "")
        try:
            return self._step(now)
        except DockingError as error:
            return self._finish(DockingOutcome.ABORTED, error.code, str(error))
        except FrameUnavailable as error:
            return self._finish(DockingOutcome.ABORTED, DockErrorCode.UNKNOWN, f"transform error: {error}")

    def _finish(self, outcome: DockingOutcome, code: DockErrorCode, message: str) -> DockingStep:
        self.result = DockingResult(outcome, code, message)
        return DockingStep(DockingState.NONE, command=STOP, result=self.result)

    def _start(self) -> DockingStep | None:
        dock_type = self.request.dock_type or self.docked_type
        plugin = self.plugin = self.database.find_plugin(dock_type)
        if plugin is None:
            known = ", ".join(sorted(self.database.plugins)) or "none"
            raise DockNotValid(
                f"no dock information to undock from: dock type '{dock_type}' is not one of the dock "
                f"plugins ({known})" if dock_type else
                f"no dock information to undock from: give dock_type (dock plugins: {known}); this server "
                "has not docked the robot")
        robot = robot_or_none(self.world, plugin.dock_frame)
        if plugin.is_charger and not plugin.is_docked(robot) and not plugin.is_charging(robot):
            return self._finish(DockingOutcome.SUCCEEDED, DockErrorCode.NONE, "")  # not in a dock
        fixed = self.params.fixed_frame
        self.staging = plugin.staging_pose(self.world.robot_pose(fixed), fixed)
        return None

    def _step(self, now: float) -> DockingStep:
        if self.plugin is None:
            finished = self._start()
            if finished is not None:
                return finished
        plugin, staging, p = self.plugin, self.staging, self.params
        assert plugin is not None and staging is not None
        limit = self.request.max_undocking_time
        if now - self.start > limit:
            raise FailedToControl(f"undocking timed out after max_undocking_time {limit:g} s")
        robot = self.world.robot_pose(p.fixed_frame)
        obstacles = self.world.obstacles()
        command = self.controller.command_to_pose(
            robot, staging, p.undock_linear_tolerance, p.undock_angular_tolerance,
            robot_in_costmap(self.world, robot, p.fixed_frame, obstacles), obstacles, False,
            not p.dock_backwards)
        if command is not None:
            return DockingStep(DockingState.NONE, command=command)
        near = robot_or_none(self.world, plugin.dock_frame)
        if plugin.is_charger and not plugin.has_stopped_charging(near):
            raise FailedToControl("reached the staging pose but the robot still charges: failed to control "
                                  "off the dock")
        self.result = DockingResult(DockingOutcome.SUCCEEDED)
        return DockingStep(DockingState.NONE, command=STOP, result=self.result)

