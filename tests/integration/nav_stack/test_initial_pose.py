"""amcl_init_pose_publisher: publishes /initialpose until amcl confirms it, or gives up after its timeout."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter

from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.localization.amcl_node import AmclNode
from nav_stack.ros.localization.initial_pose_publisher import InitialPosePublisher
from navsuite_testing.ros import spin_until, start_python, stop_process
from ros_tools.runtime.executor import make_executor
from tests.helpers.nav_ros_loc_fakes import FakeRobot

pytestmark = pytest.mark.ros


def test_publishes_until_amcl_confirms_the_seed_pose(ros_context: Any) -> None:
    amcl = AmclNode(rng=np.random.default_rng(1), context=ros_context)
    probe = Node("init_probe", context=ros_context)
    publisher = InitialPosePublisher(context=ros_context)  # seed defaults: (-2.0, -0.5, 0.0)
    executor = SingleThreadedExecutor(context=ros_context)
    for node in (amcl, probe, publisher):
        executor.add_node(node)
    try:
        robot = FakeRobot(probe, (-2.0, -0.5, 0.0))
        # AMCL is not listening yet: nothing may be published into the void.
        spin_until(executor, lambda: robot.scans >= 3, 10.0, "a few fake scans")
        assert publisher.published == 0 and publisher.done is None
        assert amcl.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert amcl.trigger_activate() == TransitionCallbackReturn.SUCCESS
        robot.publish_map()
        spin_until(executor, lambda: publisher.done is not None, 30.0, "the initial pose confirmation")
        assert publisher.done is True and publisher.published >= 1
        estimate = amcl.amcl.estimate()
        assert math.hypot(estimate.x + 2.0, estimate.y + 0.5) < 0.3
    finally:
        executor.shutdown()
        for node in (amcl, probe, publisher):
            node.destroy_node()


def test_a_restarted_amcl_gets_the_pose_the_robot_rolled_to_not_its_last_amcl_pose(ros_context: Any) -> None:
    """Issue 45: the pose re-sent to a new AMCL is the dead one's last map → odom composed with the
    odometry now; its last /amcl_pose would put the robot back where AMCL last updated."""
    amcl = AmclNode(rng=np.random.default_rng(1), context=ros_context)
    probe = Node("init_probe", context=ros_context)
    publisher = InitialPosePublisher(context=ros_context,
                                     parameter_overrides=[Parameter("resend_after_restart", value=True)])
    executor = SingleThreadedExecutor(context=ros_context)
    for node in (amcl, probe, publisher):
        executor.add_node(node)
    second = None
    try:
        robot = FakeRobot(probe, (-2.0, -0.5, 0.0))
        assert amcl.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert amcl.trigger_activate() == TransitionCallbackReturn.SUCCESS
        robot.publish_map()
        spin_until(executor, lambda: publisher.done is True, 30.0, "the initial pose confirmation")
        spin_until(executor, lambda: publisher._frames is not None and _has_map_odom(publisher), 10.0,
                   "AMCL's map -> odom in the publisher's TF buffer")
        executor.remove_node(amcl)
        amcl.destroy_node()  # the process died; its last map -> odom stays in TF
        robot.pose = (-1.6, -0.4, 0.3)  # odometry: the robot rolled on
        robot.ranges = robot._ranges()
        spin_until(executor, lambda: robot.scans >= 3, 10.0, "odometry of the rolled-on robot")
        second = AmclNode(rng=np.random.default_rng(2), context=ros_context)
        executor.add_node(second)
        assert second.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert second.trigger_activate() == TransitionCallbackReturn.SUCCESS
        robot.publish_map()
        spin_until(executor, lambda: publisher.resent == 1 and publisher.done is True, 30.0,
                   "the new AMCL's confirmation of the re-sent pose")
        x, y, yaw = publisher._target  # within the first AMCL's own error (its yaw's ~0.03 rad at 1.7 m)
        assert math.hypot(x + 1.6, y + 0.4) < 0.1 and abs(yaw - 0.3) < 0.06, publisher._target
        estimate = second.amcl.estimate()
        assert math.hypot(estimate.x + 1.6, estimate.y + 0.4) < 0.3
    finally:
        executor.shutdown()
        for node in (probe, publisher, second):
            if node is not None:
                node.destroy_node()


def _has_map_odom(publisher: InitialPosePublisher) -> bool:
    assert publisher._frames is not None
    try:
        publisher._frames.frame_pose("map", "odom")
    except FrameError:
        return False
    return True


@pytest.mark.parametrize("executor_kind", ["events", "single"])
def test_gives_up_after_its_timeout_without_amcl(ros_context: Any, executor_kind: str) -> None:
    overrides = [Parameter("timeout", value=0.5)]
    publisher = InitialPosePublisher(context=ros_context, parameter_overrides=overrides)
    executor = make_executor(executor_kind, ros_context)
    executor.add_node(publisher)
    try:
        spin_until(executor, lambda: publisher.done is not None, 10.0, "the timeout")
        assert publisher.done is False and publisher.published == 0
    finally:
        executor.shutdown()
        publisher.destroy_node()


def test_main_exits_1_after_its_timeout() -> None:
    """The process on the default EventsExecutor ends by itself (no AMCL: exit 1, no traceback)."""
    proc = start_python("nav_stack.ros.localization.initial_pose_publisher",
                        ["--ros-args", "-p", "timeout:=0.5"])
    output = stop_process(proc, timeout=30.0) if proc.wait(timeout=30.0) is not None else ""
    assert proc.returncode == 1, output
    assert "did not confirm the initial pose within 0.5 s" in output and "Traceback" not in output, output
