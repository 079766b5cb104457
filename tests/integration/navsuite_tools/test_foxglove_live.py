"""``navsuite-bag foxglove``: ROS topics streamed live through the Foxglove SDK's WebSocket server.

A websocket client speaks the Foxglove protocol to the bridge as Foxglove itself would: it reads
the channel advertisements, subscribes, and decodes the binary message frames (opcode 1, uint32
subscription id, uint64 log time in ns, then the CDR payload).
"""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import struct
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from navsuite_testing.ros import start_python, wait_until
from navsuite_tools.bag.reader import BagError
from navsuite_tools.bag.recorder import RecordOptions
from navsuite_tools.bag.schema import message_definition
from tests.helpers.streaming_cli import StreamingCli

pytestmark = pytest.mark.ros
WAIT = 20.0  # s; generous for a loaded 2-core machine
SUBPROTOCOL = "foxglove.sdk.v1"  # what foxglove-sdk 0.30 servers speak
MESSAGE_DATA = 0x01  # binary opcode of a message frame
FRAME_HEADER = struct.Struct("<BIQ")  # opcode, subscription id, log time (ns)


def _options(*topics: str, port: int = 0) -> Any:
    from navsuite_tools.bag.foxglove_live import FoxgloveOptions

    selection = RecordOptions(output=Path(os.devnull), topics=topics, discovery_period=0.2)
    return FoxgloveOptions(selection=selection, port=port)


def _recv(ws: Any, deadline: float, what: str) -> str | bytes | None:
    """One websocket message, or None if none came within a short step (the deadline still counts)."""
    if time.monotonic() > deadline:
        raise AssertionError(f"timed out after {WAIT:g} s waiting for {what}")
    try:
        return ws.recv(timeout=0.1)  # type: ignore[no-any-return]
    except TimeoutError:
        return None


def _advertised(ws: Any, topics: set[str]) -> dict[str, dict[str, Any]]:
    """Read control messages until every topic in ``topics`` is advertised; channels by topic."""
    channels: dict[str, dict[str, Any]] = {}
    deadline = time.monotonic() + WAIT
    while not topics <= channels.keys():
        message = _recv(ws, deadline, f"advertisements of {sorted(topics - channels.keys())}")
        if isinstance(message, str):
            op = json.loads(message)
            if op["op"] == "advertise":
                channels.update({channel["topic"]: channel for channel in op["channels"]})
    return channels


@pytest.fixture
def bridge(ros_context) -> Iterator[Any]:
    from navsuite_tools.bag.foxglove_live import FoxgloveBridge

    bridge = FoxgloveBridge(_options("/chatter", "/pose"), ros_context).start()
    try:
        yield bridge
    finally:
        bridge.close()


def test_topics_are_advertised_and_streamed_as_cdr(ros_context, bridge):
    import rclpy
    from geometry_msgs.msg import PoseStamped
    from rclpy.serialization import deserialize_message
    from std_msgs.msg import String
    from websockets.sync.client import connect

    node = rclpy.create_node("foxglove_test_talker", context=ros_context)
    try:
        chatter = node.create_publisher(String, "/chatter", 10)
        pose_pub = node.create_publisher(PoseStamped, "/pose", 10)
        # Connect once both channels exist: foxglove-sdk 0.30.3 can answer "Unknown channel ID" to a
        # subscribe sent within a millisecond of a channel's live advertisement (seen in some runs).
        wait_until(lambda: {"/chatter", "/pose"} <= bridge.recorder.counts.keys(), WAIT,
                   "the bridge to subscribe to /chatter and /pose")
        assert bridge.url.startswith("ws://127.0.0.1:")
        with connect(bridge.url, subprotocols=[SUBPROTOCOL], open_timeout=WAIT) as ws:
            assert ws.subprotocol == SUBPROTOCOL
            channels = _advertised(ws, {"/chatter", "/pose"})
            string_channel, pose_channel = channels["/chatter"], channels["/pose"]
            assert (string_channel["encoding"], string_channel["schemaEncoding"]) == ("cdr", "ros2msg")
            assert string_channel["schemaName"] == "std_msgs/msg/String"
            assert string_channel["schema"] == message_definition("std_msgs/msg/String")  # as in MCAP
            assert pose_channel["schemaName"] == "geometry_msgs/msg/PoseStamped"
            assert "MSG: geometry_msgs/Pose" in pose_channel["schema"]  # nested definitions included

            ws.send(json.dumps({"op": "subscribe", "subscriptions": [
                {"id": 1, "channelId": string_channel["id"]}, {"id": 2, "channelId": pose_channel["id"]}]}))
            pose = PoseStamped()
            pose.header.frame_id = "map"
            pose.pose.position.x = 1.5
            received: dict[int, tuple[int, bytes]] = {}
            deadline = time.monotonic() + WAIT
            others: list[str | bytes] = []
            frame: str | bytes | None = None
            while len(received) < 2:  # the subscriptions may match a few publishes late: publish again
                if frame is None:
                    chatter.publish(String(data="hello foxglove"))
                    pose_pub.publish(pose)
                frame = _recv(ws, deadline, f"message frames (got subscriptions {sorted(received)}, "
                                            f"counts {bridge.recorder.counts}, others {others[-5:]})")
                if isinstance(frame, bytes) and frame[0] == MESSAGE_DATA:
                    _, sub_id, log_ns = FRAME_HEADER.unpack_from(frame)
                    received[sub_id] = (log_ns, frame[FRAME_HEADER.size:])
                elif frame is not None:
                    others.append(frame)
    finally:
        node.destroy_node()

    log_ns, payload = received[1]
    assert deserialize_message(payload, String).data == "hello foxglove"
    assert log_ns > 0  # receive time on the node clock (wall time here)
    streamed = deserialize_message(received[2][1], PoseStamped)
    assert (streamed.header.frame_id, streamed.pose.position.x) == ("map", 1.5)
    assert bridge.recorder.counts["/chatter"] >= 1


def test_bad_port_and_busy_port_are_user_errors(ros_context):
    from navsuite_tools.bag.foxglove_live import FoxgloveBridge

    with pytest.raises(ValueError, match=r"port must be in 0\.\.65535, got 70000"):
        _options("/chatter", port=70000)
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with pytest.raises(BagError, match=re.escape(f"cannot serve on 127.0.0.1:{port}")):
            FoxgloveBridge(_options("/chatter", port=port), ros_context)


def test_cli_prints_the_url_serves_it_and_stops_cleanly_on_ctrl_c():
    from websockets.sync.client import connect

    url_line = re.compile(r"open (ws://127\.0\.0\.1:\d+) ")
    run = StreamingCli(start_python("navsuite_tools.bag.main", ["foxglove", "/chatter", "--port", "0"]))
    try:
        run.wait_for(lambda lines: any(url_line.search(line) for line in lines), WAIT, "the URL line")
        match = url_line.search(run.lines[0])  # the URL is the first line printed
        assert match is not None, run.lines
        with connect(match.group(1), subprotocols=[SUBPROTOCOL], open_timeout=WAIT) as ws:
            hello = json.loads(ws.recv(timeout=WAIT))
            assert (hello["op"], hello["name"]) == ("serverInfo", "navsuite-bag")
        code = run.interrupt(timeout=WAIT)
    finally:
        if run.proc.poll() is None:
            run.proc.kill()
            run.proc.wait()
    assert code == 0, run.lines
    assert run.lines[-1] == "streamed 0 messages on 0 topics"


def test_missing_sdk_is_one_line_and_exit_code_2(monkeypatch, capsys):
    from navsuite_tools.bag import main as bag_main

    monkeypatch.setitem(sys.modules, "foxglove", None)  # makes `import foxglove` raise ImportError
    set_handler: Callable[..., object] = lambda *_args: None  # noqa: E731 - keep pytest's handlers
    monkeypatch.setattr(signal, "signal", set_handler)
    assert bag_main.main(["foxglove", "-a"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [
        "navsuite-bag foxglove: the foxglove package is not installed: pip install foxglove-sdk"]
