"""docking_server over DDS against a fake kinematic robot (tests/helpers/docking_robot.py) on an
accelerated /clock: dock from 1 m in front and undock, unknown dock, lost detection, cancel, and
Nav2 Jazzy's own docking_server section with a reloaded dock database."""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from nav2_msgs.action import DockRobot, UndockRobot
from nav2_msgs.srv import ReloadDockDatabase
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.parameter import Parameter

from nav_stack.core.bt import BehaviorTreeFactory, Blackboard, NodeStatus
from nav_stack.ros.bt_nodes import BtRosContext, register_ros_nodes
from nav_stack.ros.docking.docking_server import build_nodes
from navsuite_testing.nav.world import get_result, send_goal
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.requests import call_until_answered
from tests.helpers.docking_stack import DOCK_IN_MAP, JAZZY_PARAMS, OVERRIDES, Docking
from tests.helpers.nav_ros_bt_fakes import FakeNavigateToPose

pytestmark = pytest.mark.ros


@pytest.fixture
def docking(ros_context: Any) -> Iterator[Docking]:
    stack: Docking | None = None
    try:
        stack = Docking(ros_context, OVERRIDES)
        yield stack
    finally:
        if stack is not None:
            stack.harness.close()


def test_docks_from_a_metre_in_front_then_undocks(docking: Docking) -> None:
    status, result = docking.dock()
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    assert (result.success, result.error_code, result.num_retries) == (True, 0, 0)
    robot = docking.robot
    assert robot.distance_to_dock() < 0.02  # charging starts within 2 cm (the fake battery's rule)
    assert abs(robot.robot.y) < 0.02 and abs(robot.robot.yaw) < 0.1
    states = {f.state for f in docking.feedback}
    assert DockRobot.Feedback.CONTROLLING in states
    assert DockRobot.Feedback.NAV_TO_STAGING_POSE not in states  # navigate_to_staging_pose false
    assert max(abs(v) for v, _ in robot.commands) <= 0.15 + 1e-9
    wait_until(lambda: robot.commands[-1] == (0.0, 0.0), 10.0, "the final stop command")
    wait_until(lambda: {"dock_pose", "filtered_dock_pose", "staging_pose"} <= set(docking.poses), 10.0,
               "the plugin's pose topics")
    dock_pose, staging = docking.poses["dock_pose"], docking.poses["staging_pose"]
    assert dock_pose.header.frame_id == "odom"  # refined in fixed_frame
    assert (dock_pose.pose.position.x, dock_pose.pose.position.y) == (pytest.approx(1.0, abs=0.01),
                                                                      pytest.approx(0.0, abs=0.01))
    assert staging.header.frame_id == "map"  # the database dock's frame
    assert (staging.pose.position.x, staging.pose.position.y) == (pytest.approx(1.3), pytest.approx(0.5))

    docked = robot.robot
    status, result = docking.run(UndockRobot, "undock_robot", UndockRobot.Goal())  # the docked type
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    assert (result.success, result.error_code) == (True, 0)
    back = math.hypot(robot.robot.x - docked.x, robot.robot.y - docked.y)
    print(f"\nundocking moved the robot back {back:.3f} m (staging_x_offset -0.7)")
    assert back == pytest.approx(0.7, abs=0.05 + 0.02)  # within undock_linear_tolerance of the staging pose
    wait_until(lambda: robot.commands[-1] == (0.0, 0.0), 10.0, "the final stop command")


def test_unknown_dock_lost_detection_and_cancel_end_with_their_codes(ros_context: Any) -> None:
    stack = Docking(ros_context, {**OVERRIDES, "initial_perception_timeout": 2.0})
    try:
        status, result = stack.dock("garage")
        assert (status, result.error_code, result.success) == (GoalStatus.STATUS_ABORTED,
                                                                DockRobot.Result.DOCK_NOT_IN_DB, False)
        assert "dock 'garage' is not in the dock database" in result.error_msg

        stack.robot.hidden = True  # and the last detection older than external_detection_timeout (1 s)
        hidden_at = stack.robot.sim_s
        wait_until(lambda: stack.robot.sim_s > hidden_at + 1.5, 10.0, "1.5 s of sim time")
        status, result = stack.dock()
        assert status == GoalStatus.STATUS_ABORTED
        assert result.error_code == DockRobot.Result.FAILED_TO_DETECT_DOCK
        assert "initial_perception_timeout 2 s" in result.error_msg
        assert all(command == (0.0, 0.0) for command in stack.robot.commands)  # it never moved

        stack.robot.hidden = False
        client = ActionClient(stack.probe, DockRobot, "dock_robot")
        handle = send_goal(client, DockRobot.Goal(dock_id="home_dock", navigate_to_staging_pose=False))
        wait_until(lambda: len(stack.robot.commands) > 5, 20.0, "the approach to start")
        cancel = handle.cancel_goal_async()
        wait_until(cancel.done, 10.0, "the cancel response")
        status, _ = get_result(handle, 10.0)
        assert status == GoalStatus.STATUS_CANCELED
        wait_until(lambda: stack.robot.commands[-1] == (0.0, 0.0), 10.0, "the stop command")
        assert stack.robot.distance_to_dock() > 0.3
    finally:
        stack.harness.close()


def test_jazzys_docking_section_configures_as_is_and_docks_after_a_database_reload(
        ros_context: Any, tmp_path: Path) -> None:
    """config/jazzy/nav2_params.yaml unmodified: no docks, so a dock id is DOCK_NOT_IN_DB; after
    reload_database with a dock file the same goal docks (battery status off: docked is charging)."""
    stack = Docking(ros_context, None, cli_args=["--ros-args", "--params-file", str(JAZZY_PARAMS)])
    try:
        assert stack.server.params.undock_angular_tolerance == 0.1
        assert stack.server.controller_params.v_linear_max == 0.15
        status, result = stack.dock()
        assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, DockRobot.Result.DOCK_NOT_IN_DB)
        dock_file = tmp_path / "docks.yaml"
        dock_file.write_text("docks:\n  home_dock:\n    type: simple_charging_dock\n    frame: map\n"
                             f"    pose: {DOCK_IN_MAP}\n")
        reload = stack.probe.create_client(ReloadDockDatabase, "/docking_server/reload_database")
        wait_until(reload.service_is_ready, 20.0, "the reload_database service")
        missing = ReloadDockDatabase.Request(filepath=str(tmp_path / "none.yaml"))
        bad = call_until_answered(reload, missing, 10.0)
        assert not bad.success
        assert call_until_answered(reload, ReloadDockDatabase.Request(filepath=str(dock_file)), 10.0).success
        status, result = stack.dock()
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        assert stack.robot.distance_to_dock() < 0.06
    finally:
        stack.harness.close()


DOCKING_TREE = """
<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <Sequence>
      <DockRobot dock_id="{dock}" navigate_to_staging_pose="false" success="{docked}"
                 num_retries="{retries}" error_code_id="{dock_error}" error_msg="{dock_message}"/>
      <UndockRobot success="{undocked}" error_code_id="{undock_error}"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def _tick_until_done(stack: Docking, dock_id: str) -> tuple[Any, Any]:
    """Load DOCKING_TREE with the Nav2 leaves and tick it on the executor thread until it ends."""
    ros = BtRosContext(stack.probe)
    factory = BehaviorTreeFactory()
    register_ros_nodes(factory, ros)
    board = Blackboard()
    for key, value in (("server_timeout", 2000), ("wait_for_service_timeout", 10000), ("dock", dock_id)):
        board.set(key, value)
    tree = factory.create_tree_from_text(DOCKING_TREE, blackboard=board,
                                         clock=lambda: stack.probe.get_clock().now().nanoseconds * 1e-9)
    statuses: list[Any] = [NodeStatus.RUNNING]

    def tick() -> None:
        if statuses[-1] is NodeStatus.RUNNING:
            statuses.append(tree.tick_once())

    timer = stack.probe.create_timer(0.05, tick)
    try:
        wait_until(lambda: statuses[-1] is not NodeStatus.RUNNING, 60.0, "the tree to finish")
    finally:
        stack.probe.destroy_timer(timer)
        ros.destroy()
    return statuses[-1], board


def test_the_dock_robot_and_undock_robot_leaves_run_the_server(docking: Docking) -> None:
    status, board = _tick_until_done(docking, "garage")
    assert status is NodeStatus.FAILURE
    assert (board.get("docked"), board.get("dock_error"), board.get("retries")) == (False, 901, 0)
    assert "not in the dock database" in board.get("dock_message")
    status, board = _tick_until_done(docking, "home_dock")
    assert status is NodeStatus.SUCCESS
    assert (board.get("docked"), board.get("dock_error"), board.get("retries")) == (True, 0, 0)
    assert (board.get("undocked"), board.get("undock_error")) == (True, 0)


def test_staging_navigation_is_sent_retried_once_and_failed_to_stage(ros_context: Any) -> None:
    """With dock_prestaging_tolerance 0.1 the robot (0.32 m off) is sent to the staging pose first."""
    stack = Docking(ros_context, {**OVERRIDES, "dock_prestaging_tolerance": 0.1})
    navigator = FakeNavigateToPose(context=ros_context)
    stack.harness.add(navigator)
    try:
        x, y, yaw = DOCK_IN_MAP
        staging = (x + math.cos(yaw) * -0.7, y + math.sin(yaw) * -0.7)  # staging_x_offset, in map
        navigator.failing.add(staging)
        goal = DockRobot.Goal(dock_id="home_dock", max_staging_time=60.0)
        status, result = stack.run(DockRobot, "dock_robot", goal)
        assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, DockRobot.Result.FAILED_TO_STAGE)
        assert "failed 2 times" in result.error_msg and "208" in result.error_msg
        assert navigator.goals == [staging, staging]
        navigator.failing.clear()
        status, result = stack.run(DockRobot, "dock_robot", goal)
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        assert navigator.goals == [staging] * 3
        assert DockRobot.Feedback.NAV_TO_STAGING_POSE in {f.state for f in stack.feedback}
    finally:
        stack.harness.close()


@pytest.mark.parametrize(("overrides", "message"), [
    ({"dock_plugins": []}, "docking_server: dock_plugins is empty"),
    ({"simple_charging_dock.plugin": "opennav_docking::NovaCarterDock"},
     "docking_server: simple_charging_dock.plugin 'opennav_docking::NovaCarterDock' is not one of"),
    ({"home_dock.pose": [2.0, 0.5]}, "docking_server parameters: dock 'home_dock': 'pose' must be 3 finite"),
    ({"home_dock.type": ""}, "dock 'home_dock' has no 'type'"),
    ({"controller.k_phi": 0.0}, "docking_server: invalid controller parameters: k_phi must be > 0"),
    ({"max_retries": -1}, "max_retries must be >= 0"),
])
def test_bad_configuration_fails_configure_naming_the_parameter(ros_context: Any, overrides: dict[str, Any],
                                                                message: str) -> None:
    params = [Parameter(name, value=value) for name, value in {**OVERRIDES, **overrides}.items()]
    server = build_nodes(context=ros_context, parameter_overrides=params)[0]
    try:
        with pytest.raises(ValueError, match=re.escape(message)):
            server.configure()  # type: ignore[attr-defined]
        assert server.trigger_configure() == TransitionCallbackReturn.FAILURE  # type: ignore[attr-defined]
    finally:
        server.destroy_node()
