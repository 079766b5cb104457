"""behavior_server on sim2d: spin, backup, wait, invalid input and the collision look-ahead."""

from __future__ import annotations

import math
import subprocess
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration
from geometry_msgs.msg import Point
from nav2_msgs.action import BackUp, DriveOnHeading, Spin, Wait
from rclpy.node import Node

from nav_stack.core.costmap import CostmapParams
from nav_stack.ros.behaviors.behavior_server import build_nodes
from nav_stack.ros.costmap.costmap_ros import CostmapROS
from navsuite_testing.nav.world import (
    Harness,
    WorldNode,
    get_result,
    send_goal,
    server_args,
    sim_time_override,
    start_sim,
    stop_process,
)
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient

pytestmark = pytest.mark.ros


@pytest.fixture(scope="module")
def sim() -> Iterator[subprocess.Popen[str]]:
    proc = start_sim(rtf=1.0)
    try:
        yield proc
    finally:
        stop_process(proc)


class Behaviors:
    """behavior_server plus a local costmap node (its collision input), the world and a probe."""

    def __init__(self, context: Any) -> None:
        self.harness = Harness(context)
        self.world = WorldNode(context=context)
        self.probe = Node("behavior_probe", context=context)
        self.server = build_nodes(use_sim_time=True, context=context, cli_args=server_args())[0]
        self.costmap = CostmapROS("local_costmap", defaults=CostmapParams.local_defaults(), context=context,
                                  cli_args=server_args(), parameter_overrides=sim_time_override())
        self.harness.add(self.world, self.probe, self.server, self.costmap)
        wait_until(lambda: self.world.truth is not None, 20.0, "sim2d ground truth")
        self.world.reset_sim()
        self.harness.bring_up(self.costmap)
        self.harness.bring_up(self.server)
        wait_until(self.costmap.ready.done, 40.0, "local costmap never updated")
        wait_until(lambda: self.server._grid is not None and self.server._footprint_msg is not None, 20.0,
                   "the local costmap and footprint at the behavior server")

    def run(self, action: Any, name: str, goal: Any, timeout: float = 60.0) -> tuple[int, Any]:
        return get_result(send_goal(ActionClient(self.probe, action, name), goal), timeout)


@pytest.fixture
def behaviors(ros_context: Any, sim: subprocess.Popen[str]) -> Iterator[Behaviors]:
    b: Behaviors | None = None
    try:
        b = Behaviors(ros_context)
        yield b
    finally:
        if b is not None:
            b.harness.close()


def test_spin_turns_by_the_target_angle(behaviors: Behaviors) -> None:
    _, _, yaw0 = behaviors.world.pose()
    status, result = behaviors.run(Spin, "spin", Spin.Goal(target_yaw=1.57, time_allowance=Duration(sec=10)))
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    wait_until(lambda: abs(behaviors.world.truth.twist.twist.angular.z) < 1e-3, 10.0, "the robot to stop")
    turned = math.remainder(behaviors.world.pose()[2] - yaw0, 2 * math.pi)
    print(f"\nspin 1.57 rad: turned {turned:.3f} rad (error {turned - 1.57:+.3f})")
    assert turned == pytest.approx(1.57, abs=0.1)


def test_drive_and_backup_and_the_collision_lookahead(behaviors: Behaviors) -> None:
    goal = DriveOnHeading.Goal(target=Point(x=0.5), speed=0.2, time_allowance=Duration(sec=10))
    status, result = behaviors.run(DriveOnHeading, "drive_on_heading", goal)
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    wait_until(lambda: abs(behaviors.world.truth.twist.twist.linear.x) < 1e-3, 10.0, "the robot to stop")
    print(f"\ndrive_on_heading 0.50 m: moved {behaviors.world.pose()[0] + 2.0:.3f} m")
    assert behaviors.world.pose()[0] == pytest.approx(-1.5, abs=0.06)  # + braking from 0.2 m/s
    x0, y0, _ = behaviors.world.pose()
    goal = BackUp.Goal(target=Point(x=0.3), speed=0.15, time_allowance=Duration(sec=10))
    status, result = behaviors.run(BackUp, "backup", goal)
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    wait_until(lambda: abs(behaviors.world.truth.twist.twist.linear.x) < 1e-3, 10.0, "the robot to stop")
    x1, y1, _ = behaviors.world.pose()
    print(f"\nbackup 0.30 m: moved {math.hypot(x1 - x0, y1 - y0):.3f} m")
    assert x1 < x0 and math.hypot(x1 - x0, y1 - y0) == pytest.approx(0.3, abs=0.05)
    # 1.2 m further back is the wall: the look-ahead refuses before contact.
    goal = BackUp.Goal(target=Point(x=1.2), speed=0.15, time_allowance=Duration(sec=20))
    status, result = behaviors.run(BackUp, "backup", goal)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, BackUp.Result.COLLISION_AHEAD)
    assert behaviors.world.collisions == 0


def test_invalid_input_and_wait(behaviors: Behaviors) -> None:
    goal = BackUp.Goal(target=Point(x=0.3, y=0.2), speed=0.15, time_allowance=Duration(sec=10))
    status, result = behaviors.run(BackUp, "backup", goal)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, BackUp.Result.INVALID_INPUT)
    status, result = behaviors.run(Wait, "wait", Wait.Goal(time=Duration(sec=1)))
    assert status == GoalStatus.STATUS_SUCCEEDED
    assert result.total_elapsed_time.sec + result.total_elapsed_time.nanosec * 1e-9 >= 1.0


def test_cancel_stops_a_spin(behaviors: Behaviors) -> None:
    handle = send_goal(ActionClient(behaviors.probe, Spin, "spin"),
                       Spin.Goal(target_yaw=6.0, time_allowance=Duration(sec=20)))
    wait_until(lambda: abs(behaviors.world.truth.twist.twist.angular.z) > 0.3, 20.0, "the robot to turn")
    future = handle.cancel_goal_async()
    wait_until(future.done, 10.0, "the cancel response")
    status, _ = get_result(handle, 10.0)
    assert status == GoalStatus.STATUS_CANCELED
    wait_until(lambda: abs(behaviors.world.truth.twist.twist.angular.z) < 1e-3, 10.0, "the robot to stop")
