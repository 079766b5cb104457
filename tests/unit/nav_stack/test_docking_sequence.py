"""The DockRobot and UndockRobot sequences on a kinematic world: success, every error path with its
code, retries, cancel, collisions. Times are the injected sim time (s)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import pytest

from nav_stack.core.docking.controller import DockingController, DockingControllerParams
from nav_stack.core.docking.database import Dock, DockDatabase
from nav_stack.core.docking.errors import DockErrorCode, DockingState
from nav_stack.core.docking.params import DockingServerParams
from nav_stack.core.docking.sequence import DockingSequence, DockRequest
from nav_stack.core.docking.simple_charging_dock import SimpleChargingDock, SimpleChargingDockParams
from nav_stack.core.docking.undocking import UndockingSequence, UndockRequest
from nav_stack.core.docking.world import STOP, DockingOutcome, DockingStep
from nav_stack.core.geometry import Pose2D
from tests.helpers.docking_world import JAZZY_DOCK, FakeDockingWorld, box_obstacle, drive

DOCK_IN_MAP = Pose2D(1.0, 0.5, 0.0)
MAP_TO_ODOM = Pose2D(0.5, 0.5, 0.0)  # the dock is at (0.5, 0.0) in odom
DOCK_IN_ODOM = Pose2D(0.5, 0.0, 0.0)
START = Pose2D(-0.5, 0.0, 0.0)  # 1 m before the dock
CONTROLLER = DockingControllerParams(v_linear_min=0.15, v_linear_max=0.15)  # nav2_params.yaml's


class Rig:
    """A database with one dock ``home`` (map frame), its plugin, the world and the server params."""

    def __init__(self, robot: Pose2D = START, dock: SimpleChargingDockParams = JAZZY_DOCK,
                 **params: object) -> None:
        self.world = FakeDockingWorld(robot, DOCK_IN_ODOM, MAP_TO_ODOM)
        self.plugin = SimpleChargingDock("simple_charging_dock", dock)
        home = Dock("home", "simple_charging_dock", "map", DOCK_IN_MAP)
        self.database = DockDatabase({"simple_charging_dock": self.plugin}, {"home": home})
        self.params = DockingServerParams(**params)  # type: ignore[arg-type]
        self.controller = DockingController(CONTROLLER)
        self.steps: list[DockingStep] = []

    def dock(self, now: float = 0.0, **request: object) -> DockingSequence:
        values = {"dock_id": "home", "navigate_to_staging_pose": False, **request}
        return DockingSequence(DockRequest(**values), self.params, self.controller,  # type: ignore[arg-type]
                               self.database, self.world, now)

    def undock(self, docked_type: str = "simple_charging_dock", now: float = 0.0, **request: object
               ) -> UndockingSequence:
        return UndockingSequence(UndockRequest(**request), docked_type, self.params,  # type: ignore[arg-type]
                                 self.controller, self.database, self.world, now)

    def run(self, sequence: DockingSequence | UndockingSequence, **kwargs: object
            ) -> tuple[DockingStep, float]:
        return drive(sequence, self.world, self.plugin, on_step=lambda step, _t: self.steps.append(step),
                     **kwargs)  # type: ignore[arg-type]

    def distance_to_dock(self) -> float:
        return math.hypot(self.world.robot.x - DOCK_IN_ODOM.x, self.world.robot.y - DOCK_IN_ODOM.y)


def test_docks_from_a_metre_in_front_and_reports_success() -> None:
    rig = Rig(Pose2D(-0.5, 0.1, 0.15))
    step, t = rig.run(rig.dock())
    assert step.result is not None and step.result.outcome is DockingOutcome.SUCCEEDED, step.result
    assert (step.result.error_code, step.result.num_retries) == (DockErrorCode.NONE, 0)
    assert step.result.dock_type == "simple_charging_dock"
    assert step.command == (0.0, 0.0)  # the end stops the robot
    assert rig.distance_to_dock() < JAZZY_DOCK.docking_threshold
    assert abs(rig.world.robot.y) < 0.02 and abs(rig.world.robot.yaw) < 0.1
    states = [s.state for s in rig.steps]
    assert states[0] == DockingState.CONTROLLING and DockingState.INITIAL_PERCEPTION not in states
    assert all(abs(v) <= CONTROLLER.v_linear_max + 1e-9 for v, _ in rig.world.commands)
    assert 5.0 < t < 10.0  # ~1 m at 0.15 m/s


def test_dock_backwards_backs_into_the_dock() -> None:
    rig = Rig(Pose2D(-0.5, -0.05, math.pi - 0.1), dock_backwards=True)
    step, _ = rig.run(rig.dock())
    assert step.result is not None and step.result.success, step.result
    assert rig.distance_to_dock() < JAZZY_DOCK.docking_threshold
    assert abs(math.remainder(rig.world.robot.yaw - math.pi, 2 * math.pi)) < 0.1  # facing away from the dock
    assert all(v <= 0.0 for v, _ in rig.world.commands)


def test_with_battery_status_it_settles_on_the_dock_pose_and_stops_while_waiting_for_the_charge() -> None:
    """Docked at 5 cm; while waiting for the charge the robot drives on onto the dock pose and stops
    there (a simulated base would otherwise coast past the contacts); charging starts within 2 cm."""
    rig = Rig(dock=dataclasses.replace(JAZZY_DOCK, use_battery_status=True))
    sequence = rig.dock()

    def battery(step: DockingStep, _t: float) -> None:
        rig.steps.append(step)
        rig.plugin.on_battery_current(1.0 if rig.distance_to_dock() < 0.02 and step.command == STOP else -0.5)

    step, _ = drive(sequence, rig.world, rig.plugin, on_step=battery)
    assert step.result is not None and step.result.success, step.result
    waited = [s for s in rig.steps if s.state == DockingState.WAIT_FOR_CHARGE]
    assert waited and waited[0].command is not None and waited[0].command.vx > 0.0  # on towards the dock
    assert waited[-1].command == STOP
    assert rig.distance_to_dock() < 0.01  # on the dock pose, not 5 cm short of it nor past it


def test_unknown_dock_id_is_dock_not_in_db() -> None:
    rig = Rig()
    step = rig.dock(dock_id="garage").tick(0.0)
    assert step.result is not None
    assert step.result.outcome is DockingOutcome.ABORTED
    assert step.result.error_code == DockErrorCode.DOCK_NOT_IN_DB
    assert "dock 'garage' is not in the dock database (known docks: home)" in step.result.error_msg


def test_dock_of_an_unknown_type_and_bad_poses_are_dock_not_valid() -> None:
    rig = Rig()
    rig.database.instances["odd"] = Dock("odd", "nova_carter_dock", "map", DOCK_IN_MAP)
    assert rig.dock(dock_id="odd").tick(0.0).result.error_code == DockErrorCode.DOCK_NOT_VALID  # type: ignore[union-attr]
    by_pose = rig.dock(use_dock_id=False, dock_pose=DOCK_IN_MAP, dock_frame="map", dock_type="other")
    result = by_pose.tick(0.0).result
    assert result is not None and result.error_code == DockErrorCode.DOCK_NOT_VALID
    assert "no dock plugin of type 'other'" in result.error_msg
    nan_pose = rig.dock(use_dock_id=False, dock_pose=Pose2D(math.nan, 0.0, 0.0), dock_frame="map")
    assert nan_pose.tick(0.0).result.error_code == DockErrorCode.DOCK_NOT_VALID  # type: ignore[union-attr]
    no_frame = rig.dock(use_dock_id=False, dock_pose=DOCK_IN_MAP, dock_frame="")
    assert no_frame.tick(0.0).result.error_code == DockErrorCode.DOCK_NOT_VALID  # type: ignore[union-attr]


def test_a_dock_given_by_pose_uses_the_only_plugin() -> None:
    rig = Rig()
    step, _ = rig.run(rig.dock(use_dock_id=False, dock_pose=DOCK_IN_MAP, dock_frame="map"))
    assert step.result is not None and step.result.success


def test_staging_navigation_is_tried_twice_then_failed_to_stage() -> None:
    rig = Rig(Pose2D(-3.0, 0.0, 0.0))
    sequence = rig.dock(navigate_to_staging_pose=True, max_staging_time=100.0)
    first = sequence.tick(0.0)
    assert first.state == DockingState.NAV_TO_STAGING_POSE and first.navigate is not None
    assert (first.navigate.frame, first.navigate.pose) == ("map", pytest.approx((0.3, 0.5, 0.0)))
    assert sequence.tick(1.0).navigate is None  # waiting for the navigation
    sequence.navigation_finished(False, "goal aborted by the controller")
    second = sequence.tick(2.0)
    assert second.navigate is not None and second.navigate.attempt == 2
    assert second.navigate.time_left == pytest.approx(98.0)
    sequence.navigation_finished(False, "no valid path")
    result = sequence.tick(3.0).result
    assert result is not None and result.error_code == DockErrorCode.FAILED_TO_STAGE
    assert "failed 2 times: no valid path" in result.error_msg


def test_staging_navigation_past_max_staging_time_is_cancelled() -> None:
    rig = Rig(Pose2D(-3.0, 0.0, 0.0))
    sequence = rig.dock(navigate_to_staging_pose=True, max_staging_time=10.0)
    assert sequence.tick(0.0).navigate is not None
    assert sequence.tick(10.0).result is None
    step = sequence.tick(10.05)
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_STAGE
    assert step.cancel_navigation and "max_staging_time 10 s" in step.result.error_msg


def test_a_successful_staging_navigation_leads_to_the_approach() -> None:
    rig = Rig(Pose2D(-3.0, 0.0, 0.0))
    sequence = rig.dock(navigate_to_staging_pose=True)
    goal = sequence.tick(0.0).navigate
    assert goal is not None
    rig.world.robot = Pose2D(goal.pose.x - MAP_TO_ODOM.x, goal.pose.y - MAP_TO_ODOM.y, goal.pose.yaw)
    sequence.navigation_finished(True)
    step, _ = rig.run(sequence, start=1.0)
    assert step.result is not None and step.result.success


def test_near_the_staging_pose_no_navigation_is_asked_for() -> None:
    rig = Rig(Pose2D(-0.1, 0.1, 0.1))  # the staging pose is (-0.2, 0.0) in odom: within 0.5
    rig.world.detect(rig.plugin, 0.0)
    step = rig.dock(navigate_to_staging_pose=True).tick(0.0)
    assert step.navigate is None and step.state == DockingState.CONTROLLING


def test_no_detection_is_failed_to_detect_dock_without_retries() -> None:
    rig = Rig()
    rig.world.hidden = True
    step, t = rig.run(rig.dock())
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_DETECT_DOCK
    assert step.result.num_retries == 0 and t == pytest.approx(5.0, abs=0.05)
    assert "initial_perception_timeout 5 s: no detected_dock_pose received yet" in step.result.error_msg
    assert not rig.world.commands  # it never moved


def test_approach_timeout_is_failed_to_control() -> None:
    rig = Rig(max_retries=0, dock_approach_timeout=3.0)
    rig.world.frozen = True  # the robot does not move
    step, t = rig.run(rig.dock())
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_CONTROL
    assert "dock_approach_timeout 3 s" in step.result.error_msg
    assert "all 0 retries used" in step.result.error_msg
    assert t == pytest.approx(3.0, abs=0.05) and step.result.num_retries == 1


def test_no_charge_is_retried_from_the_staging_pose_then_failed_to_charge() -> None:
    rig = Rig(dock=dataclasses.replace(JAZZY_DOCK, use_battery_status=True), max_retries=2)
    step, _ = rig.run(rig.dock(), max_s=200.0)
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_CHARGE
    assert step.result.num_retries == 3  # Nav2 counts the failure that used up the retries too
    retries = [s.num_retries for s in rig.steps]
    assert sorted(set(retries)) == [0, 1, 2, 3]
    backing = [v for v, _ in rig.world.commands if v < 0.0]
    assert backing, "the robot never drove back to the staging pose"
    assert "wait_charge_timeout 5 s" in step.result.error_msg


def test_a_lost_detection_is_retried_and_the_retry_can_succeed() -> None:
    rig = Rig()
    sequence = rig.dock()

    def hide_once(step: DockingStep, t: float) -> None:
        rig.steps.append(step)
        rig.world.hidden = 2.0 <= t < 3.5  # > external_detection_timeout during the approach

    step, _ = drive(sequence, rig.world, rig.plugin, on_step=hide_once)
    assert step.result is not None and step.result.success, step.result
    assert step.result.num_retries == 1


def test_an_obstacle_before_the_dock_ends_with_failed_to_control_and_the_robot_clear_of_it() -> None:
    """From the staging pose, a box between robot and dock: every attempt is refused before the robot
    moves into it (the dock's own last dock_collision_threshold m are not checked, the box is before)."""
    rig = Rig(Pose2D(-0.2, 0.0, 0.0), max_retries=1)
    rig.world.grid = box_obstacle(0.05, -0.3, 0.15, 0.3)
    step, _ = rig.run(rig.dock())
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_CONTROL
    assert "collision ahead" in step.result.error_msg and step.result.num_retries == 2
    assert rig.world.robot.x < 0.05 - 0.1  # the footprint (0.1 m) never touched the box
    assert step.command == (0.0, 0.0)


def test_a_collision_at_the_staging_pose_uses_one_retry_per_attempt() -> None:
    """Issue 42: from the staging pose the way back is done at once, and the approach used to run again
    in the same tick against the same costmap: all retries went within one control cycle. Each retry
    now stops the robot, returns, detects the dock again and approaches on later ticks."""
    rig = Rig(Pose2D(-0.2, 0.0, 0.0), max_retries=3)  # on the staging pose (staging_x_offset -0.7)
    rig.world.grid = box_obstacle(0.05, -0.3, 0.15, 0.3)
    ticks: list[tuple[float, DockingStep, str]] = []
    sequence = rig.dock()
    step, _ = drive(sequence, rig.world, rig.plugin,
                    on_step=lambda step, t: ticks.append((t, step, sequence.phase.value)))
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_CONTROL
    assert step.result.num_retries == 4 and "all 3 retries used" in step.result.error_msg
    counts = [0] + [s.num_retries for _, s, _ in ticks]
    failures = [i for i in range(len(ticks)) if counts[i + 1] > counts[i]]  # tick indices
    assert [counts[i + 1] - counts[i] for i in failures] == [1, 1, 1, 1]  # one retry per tick at most
    for before, after in itertools.pairwise(failures):
        phases = [phase for _, _, phase in ticks[before:after + 1]]  # each as its tick left it
        assert "back to staging" in phases and "initial perception" in phases, phases  # back, re-detect
    for index in failures[:-1]:
        assert ticks[index][1].command == (0.0, 0.0)  # the failing tick stops the robot


def test_a_retry_drives_back_to_the_staging_pose_detects_again_and_docks() -> None:
    """An obstacle seen mid-approach, gone afterwards: back to staging, a new detection, docked."""
    rig = Rig(Pose2D(-0.2, 0.0, 0.0))
    phases: list[str] = []
    xs_after_failure: list[float] = []
    sequence = rig.dock()

    def world_changes(step: DockingStep, _t: float) -> None:
        phases.append(sequence.phase.value)
        if step.num_retries == 0 and rig.world.robot.x > 0.0:
            rig.world.grid = box_obstacle(0.25, -0.3, 0.3, 0.3)  # appears in front of the robot
        elif step.num_retries == 1:
            rig.world.grid = None  # and is gone
            xs_after_failure.append(rig.world.robot.x)

    step, _ = drive(sequence, rig.world, rig.plugin, on_step=world_changes)
    assert step.result is not None and step.result.success and step.result.num_retries == 1, step.result
    assert min(xs_after_failure) < -0.2 + 0.05  # within undock_linear_tolerance of the staging pose
    retry = phases.index("back to staging")
    assert "initial perception" in phases[retry:] and "controlling" in phases[retry:]
    assert phases[retry:].index("initial perception") < phases[retry:].index("controlling")


def test_cancel_stops_the_robot_and_ends_canceled() -> None:
    rig = Rig()
    sequence = rig.dock()
    rig.world.detect(rig.plugin, 0.0)
    assert sequence.tick(0.0).command is not None
    sequence.cancel()
    step = sequence.tick(0.02)
    assert step.result is not None and step.result.outcome is DockingOutcome.CANCELED
    assert step.command == (0.0, 0.0)


def test_already_docked_succeeds_at_once() -> None:
    rig = Rig()
    rig.run(rig.dock())
    moved = len(rig.world.commands)
    step = rig.dock(now=100.0).tick(100.0)
    assert step.result is not None and step.result.success and len(rig.world.commands) == moved


def test_a_tf_failure_is_unknown() -> None:
    rig = Rig()
    rig.world.tf_broken = True
    result = rig.dock().tick(0.0).result
    assert result is not None and result.error_code == DockErrorCode.UNKNOWN
    assert result.error_msg.startswith("transform error:")


# -- undocking ------------------------------------------------------------------------------------------
def test_undock_drives_back_to_the_staging_pose() -> None:
    rig = Rig(undock_angular_tolerance=0.1)
    rig.run(rig.dock())
    docked_at = rig.world.robot
    step, _ = rig.run(rig.undock(now=50.0), start=50.0)
    assert step.result is not None and step.result.success, step.result
    assert math.hypot(rig.world.robot.x - (docked_at.x - 0.7), rig.world.robot.y - docked_at.y) < 0.05
    assert step.command == (0.0, 0.0)


def test_undock_without_dock_information_is_dock_not_valid() -> None:
    rig = Rig()
    rig.database.plugins["other"] = SimpleChargingDock("other", JAZZY_DOCK)
    result = rig.undock(docked_type="").tick(0.0).result
    assert result is not None and result.error_code == DockErrorCode.DOCK_NOT_VALID
    assert "no dock information to undock from" in result.error_msg
    result = rig.undock(dock_type="garage").tick(0.0).result
    assert result is not None and "dock type 'garage' is not one of the dock plugins" in result.error_msg


def test_undock_when_not_docked_succeeds_without_moving() -> None:
    rig = Rig()
    result = rig.undock().tick(0.0).result
    assert result is not None and result.success and not rig.world.commands


def test_undock_timeout_is_failed_to_control() -> None:
    rig = Rig()
    rig.run(rig.dock())
    rig.world.frozen = True
    step, t = rig.run(rig.undock(now=50.0, max_undocking_time=2.0), start=50.0)
    assert step.result is not None and step.result.error_code == DockErrorCode.FAILED_TO_CONTROL
    assert "max_undocking_time 2 s" in step.result.error_msg and t - 50.0 == pytest.approx(2.0, abs=0.05)
