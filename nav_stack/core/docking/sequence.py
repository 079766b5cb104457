"""The DockRobot sequence of opennav_docking, as a state object the node ticks at controller_frequency.

Nav2 runs docking as one blocking loop per goal. Here every phase is a state, and each tick (time
``now`` injected, s) does what one loop iteration does, so a node's timer drives it without blocking
and a test drives it with a fake world:

1. **resolve**: the dock by ``dock_id`` (DOCK_NOT_IN_DB, or DOCK_NOT_VALID when its type has no
   plugin) or from the request's pose and type (DOCK_NOT_VALID). A charging dock that already reports
   docked or charging succeeds at once.
2. **staging**: unless ``navigate_to_staging_pose`` is false or the robot is within
   ``dock_prestaging_tolerance`` of the staging pose, ask for a NavigateToPose there; a failed
   navigation is tried once more with the time left; past ``max_staging_time`` (or twice failed):
   FAILED_TO_STAGE, and the navigation is cancelled.
3. **initial perception**: the dock's database pose in ``fixed_frame`` is refined by the plugin until it
   succeeds, else FAILED_TO_DETECT_DOCK after ``initial_perception_timeout`` (not retried, except
   after a retry's way back, where it is that retry's failure).
4. **controlling**: each tick, docked (or charging) ends the approach; else the refined pose (lost:
   FAILED_TO_DETECT_DOCK) projected 0.25 m past the dock is the control law's target; a colliding
   command or ``dock_approach_timeout`` gives FAILED_TO_CONTROL.
5. **wait for charge** (charging docks): charging before ``wait_charge_timeout``, else FAILED_TO_CHARGE.
   Meanwhile (not in Nav2, which commands nothing and lets the base run on until contact) the robot
   settles onto the refined dock pose and stops there (see ``_settle``).

A failure in 4 or 5 is retried while ``num_retries`` <= ``max_retries``: the robot stops, drives back
to the staging pose (Nav2's resetApproach: within the undock tolerances, the roll-out checked as an
undocking motion; a collision or ``dock_approach_timeout`` there ends the goal FAILED_TO_CONTROL, as in
Nav2, where resetApproach throws outside the retry handler), detects the dock again (3) and approaches
again. Each of these hand-overs ends the tick (not in Nav2, whose loop re-runs the approach at once: a
robot still within the tolerances of the staging pose re-checked the same roll-out against the same
costmap and used up every retry within one control cycle). TF failures end the goal with UNKNOWN.
Feedback states are Nav2's (the way back reports INITIAL_PERCEPTION, as Nav2 Jazzy does).
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass

from nav_stack.core.control.base import Twist2D
from nav_stack.core.docking.controller import DockingController, relative
from nav_stack.core.docking.database import Dock, DockDatabase
from nav_stack.core.docking.errors import (
    DockErrorCode,
    DockingError,
    DockingState,
    DockNotValid,
    FailedToCharge,
    FailedToControl,
    FailedToDetectDock,
    FailedToStage,
    FrameUnavailable,
)
from nav_stack.core.docking.params import APPROACH_PROJECTION, DockingServerParams
from nav_stack.core.docking.simple_charging_dock import SimpleChargingDock
from nav_stack.core.docking.world import (
    STOP,
    DockingOutcome,
    DockingResult,
    DockingStep,
    DockingWorld,
    StagingGoal,
    robot_in_costmap,
    robot_or_none,
)
from nav_stack.core.geometry import Pose2D, angle_diff, normalize_angle

STAGING_ATTEMPTS = 2  # Nav2's navigator tries the staging navigation once more after a failure
SETTLE_TOLERANCE = 0.003  # m short of the dock pose at which the settling approach stops (one 50 Hz step)
#: s: while settling (see ``DockingSequence._settle``) the speed is capped at (distance still to go) /
#: SETTLE_TIME_CONSTANT and the heading error closes at the same rate, so the robot closes the last
#: centimetres exponentially. Not in Nav2. Why: at v_linear_min (0.15 m/s) a base that brakes at 1 m/s²
#: (the waffle; 0.9 for a Create 3) needs 1.1 cm to stop, plus 3 mm per 50 Hz cycle of command latency:
#: the robot ended 1.2-1.8 cm past the dock pose (bench/bench_docking.py). With 0.3 s the cap starts
#: 4.5 cm out, within docking_threshold, asks for 0.5 m/s² of braking and stops at about 1 cm/s.
SETTLE_TIME_CONSTANT = 0.3


class Phase(enum.Enum):
    RESOLVE = "resolve"
    STAGING = "staging"
    INITIAL_PERCEPTION = "initial perception"
    CONTROLLING = "controlling"
    WAIT_FOR_CHARGE = "wait for charge"
    RESET = "back to staging"


@dataclass(frozen=True)
class DockRequest:
    """A DockRobot goal: a dock by name (``use_dock_id``) or by pose (x m, y m, yaw rad in ``dock_frame``)
    and type; ``max_staging_time`` s for the staging navigation."""

    use_dock_id: bool = True
    dock_id: str = ""
    dock_pose: Pose2D | None = None
    dock_frame: str = ""
    dock_type: str = ""
    max_staging_time: float = 1000.0
    navigate_to_staging_pose: bool = True


def approach_target(dock: Pose2D, backwards: bool) -> Pose2D:
    """The control law's target: the dock pose moved APPROACH_PROJECTION m past the dock along its
    heading, turned round when docking backwards (the robot then faces away from the dock).

    Nav2 releases differ here: the Jazzy code turns the pose round first and projects along the turned
    heading, which puts a backwards target 0.25 m *before* the dock, where the robot circles without
    ever docking; newer Nav2 projects first, as done here.
    """
    x = dock.x + math.cos(dock.yaw) * APPROACH_PROJECTION
    y = dock.y + math.sin(dock.yaw) * APPROACH_PROJECTION
    return Pose2D(x, y, normalize_angle(dock.yaw + math.pi) if backwards else dock.yaw)


def staging_distance(robot: Pose2D, staging: Pose2D) -> float:
    """Nav2's l2Norm: sqrt(dx² + dy² + dyaw²) (m and rad mixed)."""
    return math.sqrt((robot.x - staging.x) ** 2 + (robot.y - staging.y) ** 2
                     + angle_diff(staging.yaw, robot.yaw) ** 2)


class DockingSequence:
    """One DockRobot goal, ticked until :attr:`result` is set."""

    def __init__(self, request: DockRequest, params: DockingServerParams, controller: DockingController,
                 database: DockDatabase[SimpleChargingDock], world: DockingWorld, now: float) -> None:
        self.request, self.params, self.controller = request, params, controller
        self.database, self.world = database, world
        self.phase, self.phase_start = Phase.RESOLVE, now
        self.num_retries = 0
        self.retry_reason = ""  # why the last attempt failed (the node logs it, as Nav2 does)
        self.result: DockingResult | None = None
        self.dock: Dock | None = None
        self.plugin: SimpleChargingDock | None = None
        self.staging: Pose2D | None = None  # in the dock's frame, once the dock is resolved
        self.dock_pose = Pose2D(0.0, 0.0, 0.0)  # in fixed_frame: the estimate, then the refined pose
        self._cancel_requested = False
        self._navigation: StagingGoal | None = None  # asked for and not answered yet
        self._navigation_failure: str | None = None
        self._attempts = 0
        self._handlers: dict[Phase, Callable[[float], DockingStep | None]] = {
            Phase.RESOLVE: self._resolve, Phase.STAGING: self._staging,
            Phase.INITIAL_PERCEPTION: self._perceive, Phase.CONTROLLING: self._approach,
            Phase.WAIT_FOR_CHARGE: self._wait_for_charge, Phase.RESET: self._reset}

    # -- inputs from the node -----------------------------------------------------------------------
    def cancel(self) -> None:
        """The goal was cancelled: the next tick stops the robot and ends it CANCELED."""
        self._cancel_requested = True

    def navigation_finished(self, succeeded: bool, message: str = "") -> None:
        """The staging NavigateToPose ended (``message``: its error, when it failed)."""
        if self._navigation is not None:
            self._navigation = None
            self._navigation_failure = None if succeeded else (message or "navigation failed")

    # -- the tick -------------------------------------------------------------------------------------
    def tick(self, now: float) -> DockingStep:
        """Advance by one control period; the step to carry out."""
        if self.result is not None:
            return DockingStep(DockingState.NONE, self.num_retries, result=self.result)
        if self._cancel_requested:
            return self._finish(DockingOutcome.CANCELED, DockErrorCode.NONE, "")
        for _ in range(len(Phase) + 1):  # phases may hand over within one tick; none loops back twice
            try:
                step = self._handlers[self.phase](now)
            except DockingError as error:
                step = self._on_failure(error, now)
            except FrameUnavailable as error:
                step = self._finish(DockingOutcome.ABORTED, DockErrorCode.UNKNOWN,
                                    f"transform error: {error}")
            if step is not None:
                return step
        raise RuntimeError(f"docking sequence did not settle in phase {self.phase.value}")

    def _enter(self, phase: Phase, now: float) -> None:
        self.phase, self.phase_start = phase, now

    def _elapsed(self, now: float) -> float:
        return now - self.phase_start

    def _on_failure(self, error: DockingError, now: float) -> DockingStep | None:
        # the detection after a retry's way back belongs to that retry (in Nav2 the first refinement after
        # resetApproach happens in approachDock, whose FailedToDetectDock is retried)
        retrying = self.phase is Phase.INITIAL_PERCEPTION and self.num_retries > 0
        if error.retryable and (retrying or self.phase in (Phase.CONTROLLING, Phase.WAIT_FOR_CHARGE)):
            self.num_retries += 1
            self.retry_reason = str(error)
            if self.num_retries <= self.params.max_retries:
                self.staging = self._plugin.staging_pose(self._dock.pose, self._dock.frame)
                self._enter(Phase.RESET, now)
                # stop now; the way back starts next tick, with a new robot pose and costmap
                return DockingStep(DockingState.INITIAL_PERCEPTION, self.num_retries, command=STOP)
            return self._finish(DockingOutcome.ABORTED, error.code,
                                f"{error} (all {self.params.max_retries} retries used)")
        return self._finish(DockingOutcome.ABORTED, error.code, str(error))

    def _finish(self, outcome: DockingOutcome, code: DockErrorCode, message: str) -> DockingStep:
        cancel_navigation = self._navigation is not None
        self._navigation = None
        dock_type = self._plugin.name if outcome is DockingOutcome.SUCCEEDED else ""
        self.result = DockingResult(outcome, code, message, self.num_retries, dock_type)
        return DockingStep(DockingState.NONE, self.num_retries, command=STOP,
                           cancel_navigation=cancel_navigation, result=self.result)

    @property
    def _plugin(self) -> SimpleChargingDock:
        assert self.plugin is not None, "the dock is resolved first"
        return self.plugin

    @property
    def _dock(self) -> Dock:
        assert self.dock is not None, "the dock is resolved first"
        return self.dock

    # -- phases ---------------------------------------------------------------------------------------
    def _resolve(self, now: float) -> DockingStep | None:
        request = self.request
        if request.use_dock_id:
            self.dock, self.plugin = self.database.find_dock(request.dock_id)
        else:
            pose, frame = request.dock_pose, request.dock_frame.lstrip("/")
            if pose is None or not all(math.isfinite(v) for v in pose) or not frame:
                raise DockNotValid(f"the dock pose {tuple(pose) if pose else None} in frame '{frame}' is not "
                                   "a valid pose (finite x, y, yaw and a frame name)")
            plugin = self.database.find_plugin(request.dock_type)
            if plugin is None:
                raise DockNotValid(f"no dock plugin of type '{request.dock_type}' (dock_plugins: "
                                   f"{', '.join(sorted(self.database.plugins)) or 'none'})")
            self.dock, self.plugin = Dock("", plugin.name, frame, pose), plugin
        plugin, dock = self._plugin, self._dock
        robot = robot_or_none(self.world, plugin.dock_frame)
        if plugin.is_charger and (plugin.is_docked(robot) or plugin.is_charging(robot)):
            return self._finish(DockingOutcome.SUCCEEDED, DockErrorCode.NONE, "")  # already docked
        self.staging = plugin.staging_pose(dock.pose, dock.frame)
        robot = self.world.robot_pose(dock.frame)
        if (request.navigate_to_staging_pose
                and staging_distance(robot, self.staging) >= self.params.dock_prestaging_tolerance):
            self._enter(Phase.STAGING, now)
        else:
            self._start_perception(now)
        return None

    def _staging(self, now: float) -> DockingStep | None:
        limit, staging = self.request.max_staging_time, self.staging
        assert staging is not None, "the staging pose is computed on resolving the dock"
        if self._navigation is None and self._navigation_failure is None and self._attempts > 0:
            self._start_perception(now)  # the navigation succeeded
            return None
        if self._elapsed(now) > limit:
            raise FailedToStage(f"navigation to the staging pose timed out after max_staging_time "
                                f"{limit:g} s")
        if self._navigation is None:
            if self._attempts >= STAGING_ATTEMPTS:
                raise FailedToStage(f"navigation to the staging pose failed {self._attempts} times: "
                                    f"{self._navigation_failure}")
            self._attempts += 1
            self._navigation_failure = None
            self._navigation = StagingGoal(staging, self._dock.frame, self._attempts,
                                           limit - self._elapsed(now))
            return DockingStep(DockingState.NAV_TO_STAGING_POSE, self.num_retries, navigate=self._navigation)
        return DockingStep(DockingState.NAV_TO_STAGING_POSE, self.num_retries)

    def _start_perception(self, now: float) -> None:
        dock = self._dock
        self.dock_pose = self.world.transform(dock.pose, dock.frame, self.params.fixed_frame)
        self._enter(Phase.INITIAL_PERCEPTION, now)

    def _refine(self, now: float) -> Pose2D | None:
        fixed = self.params.fixed_frame
        return self._plugin.refined_pose(self.dock_pose, fixed, now, self.world.detection_in)

    def _perceive(self, now: float) -> DockingStep | None:
        refined = self._refine(now)
        if refined is not None:
            self.dock_pose = refined
            self._enter(Phase.CONTROLLING, now)
            return None
        if self._elapsed(now) > self.params.initial_perception_timeout:
            raise FailedToDetectDock(f"no dock detection within initial_perception_timeout "
                                     f"{self.params.initial_perception_timeout:g} s: {self._plugin.failure}")
        return DockingStep(DockingState.INITIAL_PERCEPTION, self.num_retries)

    def _robot_near_dock(self, robot_fixed: Pose2D) -> Pose2D | None:
        frame = self._plugin.dock_frame
        return robot_fixed if frame == self.params.fixed_frame else robot_or_none(self.world, frame)

    def _approach(self, now: float) -> DockingStep | None:
        plugin, fixed = self._plugin, self.params.fixed_frame
        robot = self.world.robot_pose(fixed)
        near = self._robot_near_dock(robot)
        if plugin.is_docked(near) or plugin.is_charging(near):
            self._enter(Phase.WAIT_FOR_CHARGE, now)
            return None
        refined = self._refine(now)
        if refined is None:
            raise FailedToDetectDock(f"lost the dock detection during the approach: {plugin.failure}")
        self.dock_pose = refined
        target = relative(approach_target(refined, self.params.dock_backwards), robot)
        obstacles = self.world.obstacles()
        command = self.controller.command(target, robot_in_costmap(self.world, robot, fixed, obstacles),
                                          obstacles, True, self.params.dock_backwards)
        if self._elapsed(now) > self.params.dock_approach_timeout:
            raise FailedToControl(f"timed out approaching the dock after dock_approach_timeout "
                                  f"{self.params.dock_approach_timeout:g} s: neither docked nor charging")
        return DockingStep(DockingState.CONTROLLING, self.num_retries, command=command)

    def _wait_for_charge(self, now: float) -> DockingStep | None:
        plugin, fixed = self._plugin, self.params.fixed_frame
        robot = self.world.robot_pose(fixed)
        if not plugin.is_charger or plugin.is_charging(self._robot_near_dock(robot)):
            return self._finish(DockingOutcome.SUCCEEDED, DockErrorCode.NONE, "")
        if self._elapsed(now) > self.params.wait_charge_timeout:
            raise FailedToCharge(f"docked, but charging did not start within wait_charge_timeout "
                                 f"{self.params.wait_charge_timeout:g} s")
        return DockingStep(DockingState.WAIT_FOR_CHARGE, self.num_retries, command=self._settle(robot, now))

    def _settle(self, robot: Pose2D, now: float) -> Twist2D:
        """Not in Nav2: the command that brings the robot onto the dock pose and stops it there.

        Nav2 commands nothing once "docked" (``docking_threshold``, 5 cm before the dock pose): a real
        base keeps its last command until its bumper or contacts stop it on the dock. A simulated base
        coasts on for its command timeout instead (0.5 s at 0.15 m/s: 7.5 cm), past the contacts and
        into the dock. So the robot goes on towards the refined dock pose, slowing down as it closes in
        (SETTLE_TIME_CONSTANT), until base_link reaches it (SETTLE_TOLERANCE m short of it along the
        dock's heading), then stops and waits. It turns onto the dock's heading meanwhile rather than
        following the control law: 5 cm from the dock a lateral offset can no longer be corrected, and
        the law's attempts (its target lies 0.25 m past the dock, so a few millimetres of detection
        noise steer at up to 0.3 rad/s) swung the heading 0.1 rad off, the contacts' limit.
        """
        refined = self._refine(now)
        if refined is not None:
            self.dock_pose = refined
        backwards = self.params.dock_backwards
        offset = relative(self.dock_pose, robot)  # the dock in the robot frame
        ahead = -offset.x if backwards else offset.x  # m still to go
        if ahead <= SETTLE_TOLERANCE:
            return STOP
        limits = self.controller.params
        speed = min(limits.v_linear_max, ahead / SETTLE_TIME_CONSTANT)
        heading_error = normalize_angle(offset.yaw + math.pi) if backwards else offset.yaw
        turn = max(-limits.v_angular_max, min(limits.v_angular_max, heading_error / SETTLE_TIME_CONSTANT))
        return Twist2D(-speed if backwards else speed, turn)

    def _reset(self, now: float) -> DockingStep | None:
        dock, p, staging = self._dock, self.params, self.staging
        assert staging is not None, "the staging pose is computed before any approach"
        robot = self.world.robot_pose(dock.frame)
        obstacles = self.world.obstacles()
        command = self.controller.command_to_pose(
            robot, staging, p.undock_linear_tolerance, p.undock_angular_tolerance,
            robot_in_costmap(self.world, robot, dock.frame, obstacles), obstacles, False,
            not p.dock_backwards)
        if command is None:  # back at the staging pose: detect the dock again, from the next tick
            self._start_perception(now)
            return DockingStep(DockingState.INITIAL_PERCEPTION, self.num_retries, command=STOP)
        if self._elapsed(now) > p.dock_approach_timeout:
            raise FailedToControl(f"timed out returning to the staging pose for retry {self.num_retries} "
                                  f"after dock_approach_timeout {p.dock_approach_timeout:g} s")
        return DockingStep(DockingState.INITIAL_PERCEPTION, self.num_retries, command=command)
