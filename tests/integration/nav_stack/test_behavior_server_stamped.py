"""enable_stamped_cmd_vel: the servers publish TwistStamped and a stamped sim2d robot obeys them."""

from __future__ import annotations

import math
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration
from geometry_msgs.msg import TwistStamped
from nav2_msgs.action import Spin
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter

from nav_stack.ros.behaviors import behavior_server
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.control import controller_server
from navsuite_testing.nav.world import (
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

pytestmark = pytest.mark.ros


def test_stamped_commands_drive_a_stamped_robot(ros_context: Any) -> None:
    proc = start_sim(rtf=2.0, stamped=True)
    harness = Harness(ros_context)
    try:
        stamped = [Parameter("enable_stamped_cmd_vel", value=True)]
        world = WorldNode(context=ros_context)
        probe = Node("stamped_probe", context=ros_context)
        commands: list[TwistStamped] = []
        probe.create_subscription(TwistStamped, "/cmd_vel", commands.append, 10)
        behaviors = behavior_server.build_nodes(use_sim_time=True, context=ros_context,
                                                cli_args=server_args(), parameter_overrides=stamped)[0]
        controller = controller_server.build_nodes(use_sim_time=True, context=ros_context,
                                                   cli_args=server_args(), parameter_overrides=stamped)
        harness.add(world, probe, behaviors, *controller)
        wait_until(lambda: world.truth is not None, 20.0, "sim2d ground truth")
        world.reset_sim()
        harness.bring_up(behaviors)
        assert controller[0].trigger_configure() == TransitionCallbackReturn.SUCCESS
        for server in ("behavior_server", "controller_server"):
            infos = [i for i in probe.get_publishers_info_by_topic("/cmd_vel") if i.node_name == server]
            assert [i.topic_type for i in infos] == ["geometry_msgs/msg/TwistStamped"], server
        # The robot's frames cross processes after DDS discovery (sim2d is not in lockstep here): a
        # behavior asked for before the server knows base_link in odom fails with TF_ERROR, as in Nav2.
        wait_until(lambda: _knows_the_robot(behaviors), 20.0, "odom -> base_link at the behavior server")
        _, _, yaw0 = world.pose()
        handle = send_goal(ActionClient(probe, Spin, "spin"),
                           Spin.Goal(target_yaw=1.0, time_allowance=Duration(sec=10)))
        status, result = get_result(handle, 60.0)
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        assert commands and all(c.header.frame_id == "base_link" for c in commands)
        wait_until(lambda: abs(world.truth.twist.twist.angular.z) < 1e-3, 10.0, "the robot to stop")
        turned = math.remainder(world.pose()[2] - yaw0, 2 * math.pi)
        assert turned == pytest.approx(1.0, abs=0.15), "the stamped robot did not follow the commands"
    finally:
        harness.close()
        stop_process(proc)


def _knows_the_robot(server: Any) -> bool:
    try:
        server.frames.robot_pose("odom")
    except FrameError:
        return False
    return True
