"""A robot with an empty battery: the goal fails at once and its result names the battery.

nav-bringup with sim2d's battery at 0 % (a ``--sim-params`` overlay): sim2d ignores cmd_vel, the
controller sees the robot still under its commands with /battery_state at 0 % and ends FollowPath
with CONTROLLER_TIMED_OUT; Nav2's default tree does not recover from that code, so the
NavigateToPose result carries the message within one progress-checker period (10 s of sim time),
instead of minutes of spins and back-ups.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

pytest.importorskip("nav_stack.ros.bringup.nav_bringup", reason="the stack does not exist yet")

from action_msgs.msg import GoalStatus
from nav2_msgs.action import NavigateToPose
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from nav_stack.ros.common.conversions import pose_stamped
from navsuite_testing.ros import BackgroundSpin
from ros_tools.runtime.actions import ActionClient, send_until_acknowledged
from ros_tools.runtime.lockstep import LockstepParticipant
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait

pytestmark = [pytest.mark.slow, pytest.mark.ros]
PROGRESS_CHECKER_PERIOD = 10.0  # s of sim time: movement_time_allowance in config/nav2_params.yaml
CONTROLLER_TIMED_OUT = 107
# s of sim time the last feedback can precede the result: bt_navigator sends feedback every 0.05 s
# (wall), about 0.5 s of sim time at the 10x real time of a lockstep run at rtf max.
FEEDBACK_GAP = 0.5


def _seconds(duration: Any) -> float:
    return float(duration.sec) + duration.nanosec * 1e-9


@pytest.fixture
def empty_battery_stack(tmp_path: Path) -> Any:
    overlay = tmp_path / "empty_battery.yaml"
    overlay.write_text(yaml.safe_dump({"sim2d": {"ros__parameters": {"battery": {"initial_charge": 0.0}}}}))
    stack = Bringup("--sim-params", str(overlay))
    try:
        stack.wait_for_line(READY, timeout=240.0)
        yield stack
    finally:
        code = stack.stop()
        assert code in (0, 130), f"nav-bringup ended with {code}:\n{stack.output()}"


def test_an_empty_battery_fails_the_goal_with_its_cause(empty_battery_stack: Bringup,
                                                        ros_context: Any) -> None:
    node = Node("battery_empty_client", context=ros_context)
    clock: list[float] = []
    node.create_subscription(Clock, "/clock",
                             lambda m: clock.append(m.clock.sec + m.clock.nanosec * 1e-9), 10)
    client = ActionClient(node, NavigateToPose, "navigate_to_pose")
    # In lockstep, so that the simulator waits while the goal request crosses DDS (a loaded run
    # took seconds of wall time there, minutes of sim time at rtf max, before this hold).
    lockstep = LockstepParticipant(node, "battery_empty_client")
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    spin = BackgroundSpin(executor)
    try:
        wait(client.server_is_ready, 60.0, "navigate_to_pose")
        wait(lambda: bool(clock) and lockstep.reported_ns > 0, 30.0, "/clock and a first lockstep report")
        goal = NavigateToPose.Goal(pose=pose_stamped(-1.0, -0.5, 0.0, "map", node.get_clock().now().to_msg()))
        copies: list[Any] = []
        lockstep.hold(lambda: any(future.done() for future, _ in copies), 4.0)
        navigation_times: list[float] = []  # s of sim time, as bt_navigator counts them in feedback
        handle = send_until_acknowledged(
            client, goal, 30.0, copies=copies,
            feedback_callback=lambda m: navigation_times.append(_seconds(m.feedback.navigation_time)),
        ).result()
        assert handle.accepted
        result = handle.get_result_async()
        wait(result.done, 120.0, "the navigation result")
        # The server's own count (its sim clock from the goal's start), not this client's /clock:
        # under load the result crosses DDS in a wall-clock while the simulator runs on at rtf max.
        assert navigation_times, "no feedback from navigate_to_pose"
        took = max(navigation_times) + FEEDBACK_GAP
        response = result.result()
        print(f"failed after at most {took:.1f} s of sim time: {response.result.error_msg}")
        assert response.status == GoalStatus.STATUS_ABORTED
        assert response.result.error_code == CONTROLLER_TIMED_OUT, response.result.error_msg
        assert "battery empty: the robot does not respond to cmd_vel" in response.result.error_msg
        assert took < PROGRESS_CHECKER_PERIOD, f"the goal took {took:.1f} s of sim time to fail"
        assert any("battery empty" in line for line in empty_battery_stack.lines), "no warning from sim2d"
    finally:
        spin.stop()  # first: nothing may be destroyed under a spinning thread
        lockstep.destroy()
        node.destroy_node()
