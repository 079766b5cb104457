"""``ros2py action`` against a live nav2_msgs/action/Wait server, and ``ros2py interface``."""

from __future__ import annotations

import re

import pytest

from navsuite_testing.ros import wait_until
from tests.helpers.ros_cli import DISCOVERY, run_cli

FEEDBACK_STEPS = 3


@pytest.fixture
def wait_server(spinning):
    """A node serving nav2_msgs/action/Wait on /cli_wait: feedback counts down, then success."""
    nav2_msgs = pytest.importorskip("nav2_msgs.action", reason="nav2_msgs is not built into the venv yet")
    from rclpy.action import ActionServer

    Wait = nav2_msgs.Wait
    node = spinning("cli_wait_server")
    node.goals = []

    def execute(goal_handle):
        node.goals.append(goal_handle.request.time.sec)
        # Feedback is only delivered once the client's feedback subscription has matched ours.
        wait_until(lambda: node.count_subscribers("/cli_wait/_action/feedback") > 0, 10.0,
                   "the CLI's feedback subscription")
        for left in range(FEEDBACK_STEPS - 1, -1, -1):
            feedback = Wait.Feedback()
            feedback.time_left.sec = left
            goal_handle.publish_feedback(feedback)
        goal_handle.succeed()
        result = Wait.Result()
        result.total_elapsed_time.sec = goal_handle.request.time.sec
        result.error_msg = "waited"
        return result

    node.server = ActionServer(node, Wait, "cli_wait", execute)
    yield node
    node.server.destroy()


@pytest.mark.ros
def test_send_goal_prints_id_feedback_result_and_status(wait_server):
    result = run_cli("action", "send_goal", "/cli_wait", "nav2_msgs/action/Wait", "{time: {sec: 2}}",
                     "--feedback", *DISCOVERY)

    assert result.code == 0, result.output
    assert wait_server.goals == [2]
    out = result.output
    assert re.search(r"^Goal accepted with ID: [0-9a-f]{32}$", out, re.MULTILINE), out
    # Feedback may lose the race against the result at the very end, but what arrives is in order.
    seconds_left = [feedback["time_left"]["sec"] for feedback in result.blocks("Feedback")]
    assert seconds_left, out
    assert seconds_left == sorted(seconds_left, reverse=True)
    assert set(seconds_left) <= set(range(FEEDBACK_STEPS))
    assert result.blocks("Result") == [{
        "total_elapsed_time": {"sec": 2, "nanosec": 0}, "error_code": 0, "error_msg": "waited",
    }], out
    assert result.lines[-1] == "Goal finished with status: SUCCEEDED"


@pytest.mark.ros
def test_action_list_and_info_show_the_server(wait_server):
    # `action list` has no name to wait for: it prints the graph once discovery has settled. In a
    # worker that ran other tests, their participants settle first and this server's endpoints can
    # still be on the way, so the listing is polled as a user would repeat it (at most 3 times).
    for _ in range(3):
        listed = run_cli("action", "list", "-t", *DISCOVERY)
        if "/cli_wait [nav2_msgs/action/Wait]" in listed.lines:
            break
    assert "/cli_wait [nav2_msgs/action/Wait]" in listed.lines, listed.output

    info = run_cli("action", "info", "/cli_wait", *DISCOVERY)
    assert info.code == 0, info.output
    assert info.lines == [
        "Action: /cli_wait", "Action clients: 0", "Action servers: 1", "    /cli_wait_server",
    ]


@pytest.mark.ros
def test_send_goal_with_a_bad_goal_is_one_line_and_exit_1():
    result = run_cli("action", "send_goal", "/cli_wait", "std_msgs/msg/String", "{}")
    assert result.code == 1
    assert result.lines == ["'std_msgs/msg/String' is a msg type, expected an action type"], result.output


def test_interface_show_expands_nested_types():
    result = run_cli("interface", "show", "geometry_msgs/msg/PoseStamped")
    assert result.code == 0, result.output
    lines = result.lines
    assert lines[0].startswith("# A Pose with reference coordinate frame and timestamp")
    header = lines.index("std_msgs/Header header")
    assert lines[header + 1:header + 4] == [
        "\tbuiltin_interfaces/Time stamp", "\t\tint32 sec", "\t\tuint32 nanosec",
    ]
    assert "\tPoint position" in lines and "\t\tfloat64 w 1" in lines


def test_interface_show_of_a_service_keeps_the_separator():
    result = run_cli("interface", "show", "std_srvs/SetBool", "--no-comments")
    assert result.lines == ["bool data", "---", "bool success", "string message"], result.output


def test_interface_show_nav2_action_definition():
    pytest.importorskip("nav2_msgs.action", reason="nav2_msgs is not built into the venv yet")
    result = run_cli("interface", "show", "nav2_msgs/action/NavigateToPose")
    assert result.code == 0, result.output
    assert "geometry_msgs/PoseStamped pose" in result.lines
    assert result.lines.count("---") == 2


def test_interface_show_unknown_type_is_one_line_and_exit_1():
    result = run_cli("interface", "show", "no_such_msgs/msg/Thing")
    assert result.code == 1
    assert result.lines == [
        "Unknown interface type 'no_such_msgs/msg/Thing': no definition file installed for it",
    ]


def test_interface_package_lists_its_interfaces():
    result = run_cli("interface", "package", "std_srvs")
    assert result.lines == ["std_srvs/srv/Empty", "std_srvs/srv/SetBool", "std_srvs/srv/Trigger"]
