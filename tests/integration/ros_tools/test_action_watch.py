"""ros_tools.runtime.action_watch over real DDS: a goal whose server process is SIGKILLed and started
again is reported lost (the new server does not know it) long before the dead participant's lease runs
out; a goal whose server stays up is never reported, and stopping the watch ends it."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import NavigateToPose
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navsuite_testing.ros import spin_until
from ros_tools.runtime.action_watch import ServerLossWatch
from ros_tools.runtime.actions import ActionClient
from tests.helpers.held_action_server import READY_LINE

pytestmark = pytest.mark.ros
REPO = Path(__file__).resolve().parents[3]


def _server() -> subprocess.Popen[str]:
    proc = subprocess.Popen([sys.executable, "-m", "tests.helpers.held_action_server"], cwd=REPO,
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    seen = []  # Fast DDS writes its own errors to stdout (e.g. a shared-memory port it could not lock)
    for line in proc.stdout:
        if READY_LINE in line:
            return proc
        seen.append(line)
    proc.kill()  # never left behind: a second NavigateToPose server would answer the next tests' goals
    raise AssertionError(f"the held action server exited (code {proc.wait()}) before it was ready: {seen}")


@pytest.fixture
def servers() -> Iterator[list[subprocess.Popen[str]]]:
    started: list[subprocess.Popen[str]] = []
    yield started
    for proc in started:
        proc.kill()
        proc.wait()


def _accepted_goal(node: Node, executor: SingleThreadedExecutor) -> Any:
    client = ActionClient(node, NavigateToPose, "navigate_to_pose")
    spin_until(executor, client.server_is_ready, 20.0, "the server")
    future = client.send_goal_async(NavigateToPose.Goal(pose=PoseStamped()))
    spin_until(executor, future.done, 20.0, "the goal's acknowledgement")
    handle = future.result()
    assert handle.accepted
    return handle


def test_a_killed_and_respawned_server_loses_the_goal(ros_context: Any,
                                                      servers: list[subprocess.Popen[str]]) -> None:
    servers.append(_server())
    node = Node("watcher", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    handle = _accepted_goal(node, executor)
    watch = ServerLossWatch(node, NavigateToPose, "navigate_to_pose")
    lost: list[str] = []
    watch.watch(handle.goal_id, lost.append)
    executor.spin_once(timeout_sec=1.5)
    assert lost == []                                   # the server is up: nothing said
    servers[0].kill()
    servers[0].wait()
    servers.append(_server())                           # the respawn: same names, a new process
    spin_until(executor, lambda: bool(lost), 15.0, "the loss of the goal's server")  # the lease is ~20 s
    assert lost == ["the 'navigate_to_pose' server that accepted the goal is gone (a new server does not "
                    "know the goal)"]
    executor.shutdown()
    node.destroy_node()


def test_a_goal_whose_server_lives_is_never_lost_and_stop_ends_the_watch(
        ros_context: Any, servers: list[subprocess.Popen[str]]) -> None:
    servers.append(_server())
    node = Node("watcher", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    handle = _accepted_goal(node, executor)
    watch = ServerLossWatch(node, NavigateToPose, "navigate_to_pose", period_s=0.1)
    lost: list[str] = []
    stop = watch.watch(handle.goal_id, lost.append)
    timers = len(list(node.timers))
    for _ in range(20):
        executor.spin_once(timeout_sec=0.1)
    assert lost == []
    stop()
    assert len(list(node.timers)) == timers - 1
    executor.shutdown()
    node.destroy_node()
