"""The test-session hygiene of tests/conftest.py: nodes of shut-down contexts leave the ROS graph,
action servers and clients included (without that, CI's ``ros2py node list`` found earlier tests'
bt_navigator rigs late in the suite and settled before discovering its own node)."""

from __future__ import annotations

import pytest

pytest.importorskip("nav2_msgs.action")

from nav2_msgs.action import NavigateToPose
from rclpy.action import ActionClient, ActionServer

from navsuite_testing.ros import release_dds_participants
from tests.helpers.ros_cli import run_cli

pytestmark = pytest.mark.ros


def test_a_node_with_an_action_server_leaves_the_graph_after_its_context(ros_context) -> None:  # type: ignore[no-untyped-def]
    import rclpy

    node = rclpy.create_node("leftover_navigator", context=ros_context)
    kept = [ActionServer(node, NavigateToPose, "leftover_nav", lambda handle: NavigateToPose.Result()),
            ActionClient(node, NavigateToPose, "leftover_nav")]  # referenced, as a test's rig keeps them
    assert "/leftover_navigator" in run_cli("node", "list", "--timeout", "10").lines
    rclpy.shutdown(context=ros_context)
    node.destroy_node()  # what a test's teardown does; it leaves the action server and client alive
    assert release_dds_participants() >= 1
    assert "/leftover_navigator" not in run_cli("node", "list", "--timeout", "3").lines
    assert kept
