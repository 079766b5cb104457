"""controller_server on sim2d: DWB and RPP drive planned paths, preemption, cancel, selectors, error codes.

sim2d runs in lockstep with this process (the planner and controller servers spin in the harness's
executor with the ``controller_test`` participant), so the robot moves by sim time, not by how
quickly this loaded machine answers. Where a test acts on the robot's motion (a new path once it
drives), the simulator is held from the first moving command until the test has acted: a CI run on
a busy machine (2026-11-27) planned the new path 0.7 m further on than usual, next to a pillar,
and DWB found no valid trajectory from there.
"""

from __future__ import annotations

import math
import subprocess
import threading
from collections.abc import Callable, Iterator
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped, Twist
from nav2_msgs.action import ComputePathToPose, FollowPath
from nav_msgs.msg import Path
from rclpy.node import Node
from std_msgs.msg import String

from nav_stack.core.control.follow_path import Takeover
from nav_stack.ros.control import controller_server
from nav_stack.ros.planning import planner_server
from navsuite_testing.nav.world import (
    LATCHED,
    Harness,
    WorldNode,
    get_result,
    send_goal,
    server_args,
    start_sim,
    stop_process,
)
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.lockstep import LockstepParticipant

pytestmark = pytest.mark.ros
Codes = FollowPath.Result
LOCKSTEP_ROLE = "controller_test"
HOLD_GRACE = 4.0  # wall s; under the simulator's lockstep.timeout (10 s), which would drop this test


@pytest.fixture(scope="module")
def sim() -> Iterator[subprocess.Popen[str]]:
    proc = start_sim(rtf=2.0, lockstep=True)
    try:
        yield proc
    finally:
        stop_process(proc)


class Stack:
    """planner_server + controller_server with their costmaps, the world and a probe node."""

    def __init__(self, context: Any) -> None:
        self.harness = Harness(context)
        self.world = WorldNode(context=context)
        self.probe = Node("controller_probe", context=context)
        self.planner_nodes = planner_server.build_nodes(use_sim_time=True, context=context,
                                                        cli_args=server_args())
        self.controller_nodes = controller_server.build_nodes(use_sim_time=True, context=context,
                                                              cli_args=server_args())
        self.cmds: list[Twist] = []
        self.probe.create_subscription(Twist, "/cmd_vel", self._on_cmd, 100)
        self.lockstep: LockstepParticipant | None = None
        self._hold_until: Callable[[], bool] | None = None
        self.harness.add(self.world, self.probe, *self.planner_nodes, *self.controller_nodes)
        self.planner = ActionClient(self.probe, ComputePathToPose, "compute_path_to_pose")
        self.follow = ActionClient(self.probe, FollowPath, "follow_path")

    def start(self) -> None:
        wait_until(lambda: self.world.truth is not None, 20.0, "sim2d ground truth")
        self.world.reset_sim()
        self.harness.bring_up(self.planner_nodes[0])
        self.harness.bring_up(self.controller_nodes[0])
        wait_until(self.planner_nodes[1].ready.done, 40.0, "global costmap never updated")
        wait_until(self.controller_nodes[1].ready.done, 40.0, "local costmap never updated")
        self.lockstep = LockstepParticipant(self.probe, LOCKSTEP_ROLE)

    def close(self) -> None:
        self.harness.stop()  # first: a subscription destroyed under the spinning thread kills it
        if self.lockstep is not None:
            self.lockstep.destroy()  # leaves: the simulator no longer waits for this test
        self.harness.close()

    def hold_when_moving(self, until: Callable[[], bool]) -> None:
        """Hold the simulator from the first moving command (in the executor, not this thread's
        polling) until ``until()`` is true, at most HOLD_GRACE s of wall time."""
        self._hold_until = until

    def _on_cmd(self, msg: Twist) -> None:
        self.cmds.append(msg)
        if self._hold_until is not None and self.lockstep is not None and self.moving():
            self.lockstep.hold(self._hold_until, HOLD_GRACE)
            self._hold_until = None

    def plan(self, x: float, y: float, yaw: float = 0.0) -> Path:
        goal = PoseStamped()
        goal.header.frame_id = "map"
        goal.pose.position.x, goal.pose.position.y = x, y
        goal.pose.orientation.z, goal.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        status, result = get_result(send_goal(self.planner, ComputePathToPose.Goal(goal=goal)), 20.0)
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        return result.path

    def moving(self) -> bool:
        return bool(self.cmds) and abs(self.cmds[-1].linear.x) > 0.05

    def takeover(self) -> Takeover | None:
        """What the controller server's newest goal kept of the one it preempted."""
        server = self.controller_nodes[0]
        assert isinstance(server, controller_server.ControllerServer)
        return server.last_takeover


@pytest.fixture
def stack(ros_context: Any, sim: subprocess.Popen[str]) -> Iterator[Stack]:
    s = Stack(ros_context)
    try:
        s.start()
        yield s
    finally:
        s.close()


def _report(stack: Stack, goal: tuple[float, float, float], label: str) -> tuple[float, float]:
    """Errors (m, rad) of the ground-truth pose once the robot stopped.

    Only the position is asserted: the goal checker accepts the yaw within 0.25 rad while the robot
    may still turn at up to 1.8 rad/s (RPP's rotate_to_heading_angular_vel), and the waffle brakes
    at 2 rad/s², so the stopped yaw lies further off; it is printed for the report.
    """
    twist = lambda: stack.world.truth.twist.twist  # noqa: E731
    wait_until(lambda: abs(twist().linear.x) < 1e-3 and abs(twist().angular.z) < 1e-3, 10.0, "a stop")
    x, y, yaw = stack.world.pose()
    xy_error = math.hypot(x - goal[0], y - goal[1])
    yaw_error = abs(math.remainder(yaw - goal[2], 2 * math.pi))
    print(f"\n{label}: final position error {xy_error:.3f} m, yaw error {yaw_error:.3f} rad")
    return xy_error, yaw_error


def test_rpp_follows_a_planned_path_to_the_goal(stack: Stack) -> None:
    path = stack.plan(2.0, 0.0)
    handle = send_goal(stack.follow, FollowPath.Goal(path=path, controller_id="FollowPath",
                                                     goal_checker_id="general_goal_checker"))
    status, result = get_result(handle, 120.0)
    assert status == GoalStatus.STATUS_SUCCEEDED, (result.error_code, result.error_msg, stack.world.pose())
    xy_error, _ = _report(stack, (2.0, 0.0, 0.0), "RPP to (2.0, 0.0)")
    assert xy_error < 0.25 + 0.05
    assert stack.world.collisions == 0
    wait_until(lambda: stack.cmds[-1].linear.x == 0.0 and stack.cmds[-1].angular.z == 0.0, 5.0,
               "a final zero command")


def test_dwb_takes_a_new_path_without_stopping(stack: Stack) -> None:
    replaced = threading.Event()
    stack.hold_when_moving(replaced.is_set)
    first = send_goal(stack.follow, FollowPath.Goal(path=stack.plan(2.0, 0.0), controller_id="DWB"))
    local_plans: list[Path] = []
    stack.probe.create_subscription(Path, "/local_plan", local_plans.append, 10)
    wait_until(stack.moving, 30.0, "the robot to drive")
    new_path = stack.plan(0.0, 2.0, math.pi / 2)
    seen = len(stack.cmds)
    second = send_goal(stack.follow, FollowPath.Goal(path=new_path, controller_id="DWB"))
    replaced.set()
    status, result = get_result(first, 10.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, Codes.NONE)
    assert "preempted" in result.error_msg
    assert stack.takeover() is Takeover.NEW_PATH
    status, result = get_result(second, 120.0)
    assert status == GoalStatus.STATUS_SUCCEEDED, (result.error_code, result.error_msg, stack.world.pose())
    xy_error, _ = _report(stack, (0.0, 2.0, math.pi / 2), "DWB to (0.0, 2.0) after a new path")
    assert xy_error < 0.25 + 0.05
    assert stack.world.collisions == 0
    during = stack.cmds[seen:]
    first_stop = next(i for i, c in enumerate(during) if c.linear.x == 0.0 and c.angular.z == 0.0)
    assert first_stop > 0.8 * len(during), "the robot stopped when the path was replaced"
    assert local_plans and local_plans[-1].header.frame_id == "odom"


def test_a_replan_toward_the_same_goal_only_swaps_the_path(stack: Stack) -> None:
    """The bt_navigator's 1 Hz replan: the same goal planned again from where the robot now is. Nav2's
    protocol holds (the old goal ends ABORTED "preempted", the new one drives on to SUCCEEDED) and the
    controller takes the plan as the rest of its path (follow_path.Takeover.REMAINDER)."""
    replaced = threading.Event()
    stack.hold_when_moving(replaced.is_set)
    first = send_goal(stack.follow, FollowPath.Goal(path=stack.plan(2.0, 0.0)))
    wait_until(stack.moving, 30.0, "the robot to drive")
    assert stack.takeover() is Takeover.FRESH
    second = send_goal(stack.follow, FollowPath.Goal(path=stack.plan(2.0, 0.0)))
    replaced.set()
    status, result = get_result(first, 10.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, Codes.NONE)
    assert "preempted" in result.error_msg
    assert stack.takeover() is Takeover.REMAINDER
    status, result = get_result(second, 120.0)
    assert status == GoalStatus.STATUS_SUCCEEDED, (result.error_code, result.error_msg, stack.world.pose())
    xy_error, _ = _report(stack, (2.0, 0.0, 0.0), "to (2.0, 0.0) after a replan")
    assert xy_error < 0.25 + 0.05
    assert stack.world.collisions == 0


def test_cancel_stops_the_robot_at_once(stack: Stack) -> None:
    handle = send_goal(stack.follow, FollowPath.Goal(path=stack.plan(2.0, 0.0)))
    wait_until(stack.moving, 30.0, "the robot to drive")
    future = handle.cancel_goal_async()
    wait_until(future.done, 10.0, "the cancel response")
    after = len(stack.cmds)
    status, _ = get_result(handle, 10.0)
    assert status == GoalStatus.STATUS_CANCELED
    wait_until(lambda: stack.cmds[-1].linear.x == 0.0 and stack.cmds[-1].angular.z == 0.0, 5.0,
               "a zero command")
    # At most the one command already in flight when the cancel was accepted may still move the robot.
    moving = [c for c in stack.cmds[after:] if c.linear.x != 0.0 or c.angular.z != 0.0]
    assert len(moving) <= 1, "motion commands were published after the cancel was accepted"
    wait_until(lambda: abs(stack.world.truth.twist.twist.linear.x) < 1e-3, 10.0, "the robot to stop")


def test_bad_goals_and_selectors(stack: Stack) -> None:
    status, result = get_result(send_goal(stack.follow, FollowPath.Goal(path=Path())), 10.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, Codes.INVALID_PATH)
    path = stack.plan(0.0, 2.0)
    goal = FollowPath.Goal(path=path, controller_id="Nope")
    status, result = get_result(send_goal(stack.follow, goal), 10.0)
    assert result.error_code == Codes.INVALID_CONTROLLER and "Nope" in result.error_msg
    elsewhere = Path(header=path.header, poses=path.poses)
    elsewhere.header.frame_id = "no_such_frame"
    status, result = get_result(send_goal(stack.follow, FollowPath.Goal(path=elsewhere)), 10.0)
    assert result.error_code == Codes.TF_ERROR
    selector = stack.probe.create_publisher(String, "/controller_selector", LATCHED)
    selector.publish(String(data="NotAController"))
    server = stack.controller_nodes[0]
    wait_until(lambda: server._selectors[0].selected == "NotAController", 10.0, "the selection")
    status, result = get_result(send_goal(stack.follow, FollowPath.Goal(path=path)), 10.0)
    assert result.error_code == Codes.INVALID_CONTROLLER, "an empty controller_id ignored the selector"
    status, result = get_result(
        send_goal(stack.follow, FollowPath.Goal(path=path, goal_checker_id="no_checker")), 10.0)
    assert result.error_code == Codes.INVALID_CONTROLLER
