"""Service-calling BT leaves (nav2_behavior_tree ``BtServiceNode``): ClearEntireCostmap.

The request goes out on the first tick; the leaf stays RUNNING until the response arrives and
fails when the service does not appear within ``wait_for_service_timeout`` or does not answer
within ``server_timeout`` ms (the node's clock, see ``BtRosContext``), as Nav2's "Node timed out
while executing service call".
"""

from __future__ import annotations

import contextlib
from typing import Any, ClassVar

from nav2_msgs.srv import ClearEntireCostmap
from rclpy.task import Future

from nav_stack.core.bt import BtPortError, NodeConfig, PortList, StatefulActionNode, input_port
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.action_node import DEFAULT_SERVER_TIMEOUT_MS, DEFAULT_WAIT_FOR_SERVICE_MS
from nav_stack.ros.bt_nodes.context import BtRosContext, LeafFailure, TimedRequest


class BtServiceNode(StatefulActionNode):
    """Calls ``service_name`` once per run; SUCCESS when it answers in time."""

    srv_type: ClassVar[Any] = None
    default_service_name: ClassVar[str] = ""

    def __init__(self, name: str, config: NodeConfig, *, ros: BtRosContext) -> None:
        super().__init__(name, config)
        self.ros = ros
        self._future: Future | None = None
        self._deadline = 0.0
        self._timing: TimedRequest | None = None  # the request's answer, timed
        with contextlib.suppress(BtPortError):  # created at load so discovery is done by the first tick
            self._client()

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("service_name", str, cls.default_service_name, "service to call"),
            input_port("server_timeout", int, "{server_timeout}", "ms the service may take to answer"),
        )

    def make_request(self) -> Any:
        """The request to send."""
        return self.srv_type.Request()

    def _client(self) -> Any:
        return self.ros.service_client(self.srv_type, str(self.get_input("service_name")))

    def _fail(self, message: str) -> NodeStatus:
        service = str(self.get_input("service_name"))
        self.ros.record_failure(self.config.path, LeafFailure(service, 0, "", message))
        self.ros.node.get_logger().warn(f"{self.name}: {message}")
        return NodeStatus.FAILURE

    def _send(self) -> None:
        self._future = self._client().call_async(self.make_request())
        self._timing = self.ros.start_timed(self._future)  # server_timeout counts sim time, not DDS's

    def on_start(self) -> NodeStatus:
        self._future = None
        if self._client().service_is_ready():
            self._send()
        else:
            wait_ms = int(self.config.blackboard.get("wait_for_service_timeout", DEFAULT_WAIT_FOR_SERVICE_MS))
            self._deadline = self.ros.wall_clock() + wait_ms / 1000.0
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        if self._future is None:
            if self._client().service_is_ready():
                self._send()
                return NodeStatus.RUNNING
            if self.ros.wall_clock() > self._deadline:
                return self._fail(f"service '{self.get_input('service_name')}' is not available")
            return NodeStatus.RUNNING
        if self._future.done():
            self._future = None
            return NodeStatus.SUCCESS
        timeout_ms = int(self.get_input_or("server_timeout", DEFAULT_SERVER_TIMEOUT_MS))
        assert self._timing is not None
        if self.ros.waited_ms(self._timing) > timeout_ms:
            self._future = None
            service = self.get_input("service_name")
            return self._fail(f"service '{service}' did not answer within {timeout_ms} ms")
        return NodeStatus.RUNNING

    def on_halted(self) -> None:
        self._future = None


class ClearEntireCostmapService(BtServiceNode):
    """Clear a whole costmap (``<costmap>/clear_entirely_<costmap>``)."""

    srv_type = ClearEntireCostmap
    default_service_name = "local_costmap/clear_entirely_local_costmap"
