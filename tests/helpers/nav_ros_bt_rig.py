"""A bt_navigator (or waypoint_follower) under test, the scripted FakeNav2 and a client node, spun
by the production executor (one thread, in the background); lifecycle transitions from the test thread."""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from rclpy.node import Node
from rclpy.parameter import Parameter

from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient, send_until_acknowledged
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.runner import spin_until_shutdown
from tests.helpers.nav_ros_bt_fakes import FakeNav2

#: Python on a loaded machine needs more than Nav2's 20 ms to acknowledge a goal and 1 s for discovery.
NAVIGATOR_OVERRIDES = [Parameter("default_server_timeout", value=2000),
                       Parameter("wait_for_service_timeout", value=10000)]


@dataclass
class Rig:
    """The node under test, the fakes and a client node."""

    node: Any
    fake: FakeNav2
    client: Node
    executor: Any
    thread: threading.Thread
    feedback: list[Any] = field(default_factory=list)
    stopping: bool = False

    def wait(self, predicate: Callable[[], bool], what: str, timeout: float = 20.0) -> None:
        wait_until(predicate, timeout, what)

    def action_client(self, action_type: Any, name: str) -> ActionClient:
        client = ActionClient(self.client, action_type, name)
        self.wait(client.server_is_ready, f"the {name} server")
        return client

    def _on_feedback(self, msg: Any) -> None:
        self.feedback.append(msg.feedback)

    def send(self, client: ActionClient, goal: Any) -> Any:
        """Send ``goal`` until acknowledged; the (accepted) goal handle."""
        handle = send_until_acknowledged(client, goal, 20.0, feedback_callback=self._on_feedback).result()
        assert handle.accepted, "goal rejected"
        return handle

    def result(self, handle: Any, timeout: float = 30.0) -> Any:
        future = handle.get_result_async()
        self.wait(future.done, "the goal's result", timeout)
        return future.result()


def start_rig(context: Any, make_node: Callable[..., Any], **fake_kwargs: Any) -> Rig:
    """Build and activate the node under test (``make_node(context=...)``) next to FakeNav2."""
    fake = FakeNav2(context=context, **fake_kwargs)
    node = make_node(context=context)
    client = Node("test_client", context=context)
    executor = make_executor(context=context)
    for each in (fake, node, client):
        executor.add_node(each)
    rig = Rig(node, fake, client, executor, threading.Thread())
    rig.thread = threading.Thread(target=spin_until_shutdown, args=(executor, "bt rig", lambda: rig.stopping),
                                  daemon=True)
    rig.thread.start()
    node.trigger_configure()
    node.trigger_activate()
    return rig


def stop_rig(rig: Rig) -> None:
    rig.stopping = True  # stop spinning first: see ros_tools.runtime.runner.spin_until_shutdown
    rig.thread.join(timeout=5.0)
    rig.executor.shutdown()
    for each in (rig.client, rig.node, rig.fake):
        each.destroy_node()
