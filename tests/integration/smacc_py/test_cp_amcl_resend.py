"""CpAmcl sends an initial pose again on the wall clock until AMCL answers it with an estimate.

A pose published before DDS has matched AMCL's subscription is lost (the topic is volatile). In
lockstep, sim time waits for AMCL's answer, so the behavior's sim-time republish cannot help: the
component resends every RESEND_WALL_S wall seconds, for at most DISCOVERY_HOLD_S (bench_mission:
StSetInitialPose lasted 0 to 1.34 s of sim time before this, 0 s in 10 of 10 runs after).
"""

from __future__ import annotations

from typing import Any

import pytest
from geometry_msgs.msg import PoseWithCovarianceStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navsuite_testing.ros import BackgroundSpin, wait_until
from smacc_py.clients.cl_nav2z.cp_amcl import AMCL_POSE_QOS, CpAmcl
from smacc_py.ros.context import RosContext, attach_ros_context

pytestmark = pytest.mark.ros


class StandInMachine:
    """What CpAmcl asks of its machine: the clock (s) and, through the ROS context, the node."""

    def now(self) -> float:
        return 0.0


def _component(node: Node) -> CpAmcl:
    machine = StandInMachine()
    attach_ros_context(machine, RosContext(node))
    amcl = CpAmcl()
    amcl.sm = machine  # type: ignore[assignment]
    amcl.on_initialize()
    return amcl


def test_a_pose_sent_before_amcl_listens_arrives_and_the_answer_stops_the_copies(ros_context: Any) -> None:
    machine_node = Node("cp_amcl_machine", context=ros_context)
    amcl = _component(machine_node)
    amcl.set_initial_pose(1.0, 2.0, 0.5)  # nobody subscribes yet: this copy is lost

    amcl_node = Node("cp_amcl_stand_in_amcl", context=ros_context)
    received: list[PoseWithCovarianceStamped] = []
    amcl_node.create_subscription(PoseWithCovarianceStamped, "initialpose", received.append, 10)
    answers = amcl_node.create_publisher(PoseWithCovarianceStamped, "amcl_pose", AMCL_POSE_QOS)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(machine_node)
    executor.add_node(amcl_node)
    spin = BackgroundSpin(executor, "cp_amcl")
    try:
        wait_until(lambda: bool(received), 5.0, "a copy of the initial pose")
        assert (received[0].pose.pose.position.x, received[0].pose.pose.position.y) == (1.0, 2.0)
        answers.publish(received[0])  # AMCL's estimate at the pose it took
        wait_until(lambda: amcl.last_estimate is not None, 5.0, "the answer")
        wait_until(amcl._resend_timer.is_canceled, 5.0, "the copies to stop")
    finally:
        spin.stop(machine_node, amcl_node)


def test_copies_stop_after_the_hold_when_amcl_never_answers(ros_context: Any) -> None:
    machine_node = Node("cp_amcl_machine_unanswered", context=ros_context)
    listener = Node("cp_amcl_listener", context=ros_context)
    received: list[PoseWithCovarianceStamped] = []
    listener.create_subscription(PoseWithCovarianceStamped, "initialpose", received.append, 10)
    amcl = _component(machine_node)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(machine_node)
    executor.add_node(listener)
    spin = BackgroundSpin(executor, "cp_amcl_unanswered")
    try:
        executor.create_task(lambda: amcl.set_initial_pose(0.0, 0.0, 0.0))
        wait_until(lambda: len(received) >= 2, 5.0, "the first copies")
        wait_until(amcl._resend_timer.is_canceled, 10.0, "the copies to stop after DISCOVERY_HOLD_S")
        # DISCOVERY_HOLD_S / RESEND_WALL_S copies at most, and the original
        assert len(received) <= 9
        assert amcl.published == [(0.0, 0.0, 0.0)]
    finally:
        spin.stop(machine_node, listener)
