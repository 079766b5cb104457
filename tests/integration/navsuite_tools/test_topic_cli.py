"""``ros2py topic`` against live nodes: echo, pub, list, info, hz and the error cases."""

from __future__ import annotations

import re

import pytest
import yaml

from navsuite_testing.ros import wait_until
from tests.helpers.ros_cli import DISCOVERY, run_cli

pytestmark = pytest.mark.ros


def _pose_talker(spinning, period: float = 0.05):
    """A node publishing a fixed PoseStamped on /cli_pose every ``period`` seconds; returns the message."""
    from geometry_msgs.msg import PoseStamped

    node = spinning("cli_talker")
    msg = PoseStamped()
    msg.header.frame_id = "map"
    msg.header.stamp.sec = 17
    msg.pose.position.x = 1.25
    msg.pose.orientation.z, msg.pose.orientation.w = 0.6, 0.8
    publisher = node.create_publisher(PoseStamped, "cli_pose", 10)
    node.create_timer(period, lambda: publisher.publish(msg))
    return msg


def test_echo_once_prints_the_message_as_yaml_and_a_separator(spinning):
    from ros_tools.convert import message_to_dict

    sent = _pose_talker(spinning)
    result = run_cli("topic", "echo", "/cli_pose", "--once", *DISCOVERY)

    assert result.code == 0, result.output
    body, separator, rest = result.output.partition("---\n")
    assert separator and rest == ""
    assert yaml.safe_load(body) == message_to_dict(sent)


def test_echo_field_with_explicit_short_type_prints_only_that_field(spinning):
    _pose_talker(spinning)
    result = run_cli("topic", "echo", "cli_pose", "geometry_msgs/PoseStamped", "--once",
                     "--field", "pose.position.x", *DISCOVERY)
    assert result.code == 0, result.output
    assert result.lines == ["1.25", "---"]


def test_pub_once_reaches_a_subscriber(spinning):
    from geometry_msgs.msg import Twist

    node = spinning("cli_listener")
    received: list[Twist] = []
    node.create_subscription(Twist, "cli_cmd", received.append, 10)

    result = run_cli("topic", "pub", "--once", "/cli_cmd", "geometry_msgs/msg/Twist",
                     "{linear: {x: 0.3}, angular: {z: -0.5}}", *DISCOVERY)

    assert result.code == 0, result.output
    assert result.lines[0] == "publisher: beginning loop"
    assert result.lines[1].startswith(
        "publishing #1: geometry_msgs.msg.Twist(linear=geometry_msgs.msg.Vector3(x=0.3")
    wait_until(lambda: len(received) == 1, 10.0, "the published Twist")
    assert (received[0].linear.x, received[0].angular.z) == (0.3, -0.5)


def test_pub_times_publishes_exactly_that_many_messages(spinning):
    from std_msgs.msg import String

    node = spinning("cli_listener")
    received: list[str] = []
    node.create_subscription(String, "cli_chatter", lambda m: received.append(m.data), 10)

    result = run_cli("topic", "pub", "/cli_chatter", "std_msgs/msg/String", "data: hello", "-t", "3",
                     "-r", "20", *DISCOVERY)

    assert result.code == 0, result.output
    assert [line for line in result.lines if line.startswith("publishing #")] == [
        f"publishing #{i}: std_msgs.msg.String(data='hello')" for i in (1, 2, 3)
    ]
    wait_until(lambda: len(received) == 3, 10.0, "three messages")
    assert received == ["hello"] * 3


def test_list_with_types_and_verbose_info_describe_the_topic(spinning):
    _pose_talker(spinning)

    listed = run_cli("topic", "list", "-t", *DISCOVERY)
    assert listed.code == 0, listed.output
    assert "/cli_pose [geometry_msgs/msg/PoseStamped]" in listed.lines
    assert not any("/_action/" in line for line in listed.lines)

    info = run_cli("topic", "info", "/cli_pose", "-v", *DISCOVERY)
    assert info.code == 0, info.output
    assert info.lines[0] == "Type: geometry_msgs/msg/PoseStamped"
    assert "Publisher count: 1" in info.lines
    assert "Node name: cli_talker" in info.lines
    assert "Endpoint type: PUBLISHER" in info.lines
    assert "Subscription count: 0" in info.lines


def test_hz_reports_rate_statistics_over_the_window(spinning, stream_cli):
    _pose_talker(spinning, period=0.05)
    hz = stream_cli("topic", "hz", "/cli_pose", "--window", "5", *DISCOVERY)

    hz.wait_for(lambda lines: any("window:" in line for line in lines), 30.0, "an hz report")
    assert hz.interrupt() == 0
    index = next(i for i, line in enumerate(hz.lines) if "window:" in line)
    rate = re.fullmatch(r"average rate: (\d+\.\d{3})", hz.lines[index - 1])
    stats = re.fullmatch(r"\tmin: \d+\.\d{3}s max: \d+\.\d{3}s std dev: \d+\.\d{5}s window: (\d+)",
                         hz.lines[index])
    assert rate is not None and stats is not None, hz.lines
    assert float(rate.group(1)) > 0.0
    assert 2 <= int(stats.group(1)) <= 5


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["topic", "info", "/cli_missing", "--timeout", "1"],
         "Unknown topic '/cli_missing' (waited 1.0 s for it to appear)"),
        (["topic", "echo", "/cli_missing", "--timeout", "1"],
         "Unknown topic '/cli_missing' (waited 1.0 s for it to appear)"),
        (["topic", "echo", "/cli_missing", "no_such_msgs/msg/Thing"],
         "unknown msg type 'no_such_msgs/msg/Thing': cannot import no_such_msgs.msg "
         "(No module named 'no_such_msgs')"),
        (["topic", "pub", "/cli_x", "std_msgs/msg/String", "{data: [1"],
         "malformed YAML '{data: [1': expected ',' or ']', but got '<stream end>' (line 1, column 10)"),
        (["topic", "pub", "/cli_x", "std_msgs/msg/String", "{dta: hi}"],
         "std_msgs/msg/String: no field 'dta' (fields: data)"),
        (["topic", "pub", "/cli_x", "std_msgs/msg/Strin", "{}"],
         "unknown msg type 'std_msgs/msg/Strin': std_msgs.msg has no type 'Strin'"),
    ],
)
def test_user_errors_are_one_line_and_exit_code_1(args, message):
    result = run_cli(*args)
    assert result.code == 1
    assert result.lines == [message], result.output
