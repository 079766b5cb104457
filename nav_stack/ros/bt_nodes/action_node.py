"""Base of the BT leaves that call a Nav2 action server (nav2_behavior_tree ``BtActionNode``).

Semantics, as in Nav2 Jazzy, without ever blocking a tick:

* first tick: build the goal from the ports and send it (after waiting, across ticks, up to
  ``wait_for_service_timeout`` for the server to appear); RUNNING.
* the server must acknowledge within ``server_timeout`` ms or the leaf fails ("Timed out while
  waiting for action server to acknowledge goal request"); a rejected goal fails. The time is the
  node's (sim time under ``use_sim_time``, see ``BtRosContext``); the wait for the server to
  appear is wall time.
* while the goal runs, ``updated_goal()`` may return a new goal (FollowPath does when the planner
  produced a new path): it is sent and the server preempts the old one.
* SUCCEEDED → SUCCESS and ``error_code_id`` ← 0; ABORTED → FAILURE and ``error_code_id`` ← the
  server's code; CANCELED → SUCCESS (Nav2's ``on_cancelled``).
* halt: the running goal is cancelled (also one that is acknowledged after the halt).

Every outcome other than success is also recorded in the shared context so the navigator can
report which server failed, with which code and message.
"""

from __future__ import annotations

import contextlib
import enum
from typing import Any, ClassVar

from action_msgs.msg import GoalStatus
from rclpy.action.client import ClientGoalHandle
from rclpy.task import Future

from nav_stack.core.bt import BtPortError, NodeConfig, PortList, StatefulActionNode, input_port, output_port
from nav_stack.core.bt.ports import blackboard_key
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.context import BtRosContext, LeafFailure, TimedRequest, code_name
from ros_tools.runtime.actions import cancel_if_accepted

DEFAULT_SERVER_TIMEOUT_MS = 20  # Nav2's default_server_timeout
DEFAULT_WAIT_FOR_SERVICE_MS = 1000  # Nav2's wait_for_service_timeout


class _Phase(enum.Enum):
    WAITING_FOR_SERVER = "waiting for server"
    SENT = "sent"
    ACTIVE = "active"


def common_ports(server_name: str) -> PortList:
    """Ports every action leaf has: server_name, server_timeout (ms), error_code_id."""
    return (
        input_port("server_name", str, server_name, "action server name"),
        input_port("server_timeout", int, "{server_timeout}", "ms the server may take to acknowledge a goal"),
        output_port("error_code_id", int, description="the server's error code (0 on success)"),
    )


class BtActionNode(StatefulActionNode):
    """Sends one goal per run to ``server_name``; subclasses build the goal and read the result."""

    action_type: ClassVar[Any] = None
    default_server_name: ClassVar[str] = ""

    def __init__(self, name: str, config: NodeConfig, *, ros: BtRosContext) -> None:
        super().__init__(name, config)
        self.ros = ros
        self._phase = _Phase.WAITING_FOR_SERVER
        self._deadline = 0.0
        self._timing: TimedRequest | None = None  # the goal request's acknowledgement, timed
        self._goal: Any = None
        self._goal_future: Future | None = None
        self._handle: ClientGoalHandle | None = None
        self._result_future: Future | None = None
        self._prepare_client()

    def _prepare_client(self) -> None:
        """Create the client when the tree loads (as Nav2 does) so discovery is done by the first tick."""
        with contextlib.suppress(BtPortError):  # a server_name from the blackboard: made on first use
            self.ros.action_client(self.action_type, self.server_name)

    @classmethod
    def provided_ports(cls) -> PortList:
        return common_ports(cls.default_server_name)

    # -- hooks -------------------------------------------------------------------------------------
    def make_goal(self) -> Any:
        """The goal to send, from the ports; None (after logging why) makes the leaf fail."""
        raise NotImplementedError

    def on_success(self, result: Any) -> NodeStatus:
        """Write output ports from a SUCCEEDED result."""
        return NodeStatus.SUCCESS

    def on_aborted(self, result: Any) -> None:
        """Called with the result of an aborted goal, before the leaf fails: write result outputs here."""

    def updated_goal(self) -> Any:
        """A replacement goal while the current one runs (e.g. a new path), else None."""
        return None

    # -- helpers -----------------------------------------------------------------------------------
    @property
    def server_name(self) -> str:
        return str(self.get_input("server_name"))

    def _fail(self, message: str, code: int = 0) -> NodeStatus:
        name = code_name(self.action_type.Result, code) if code else ""
        failure = LeafFailure(self.server_name, code, name, message)
        key = blackboard_key(str(self.raw_port("error_code_id") or "")) or self.config.path
        self.ros.record_failure(key, failure)
        if code == 0:  # rclpy needs one severity per logging call site
            self.ros.node.get_logger().warn(f"{self.name}: {failure.describe()}")
        else:
            self.ros.node.get_logger().info(f"{self.name}: {failure.describe()}")
        return NodeStatus.FAILURE

    def _send(self, goal: Any) -> None:
        client = self.ros.action_client(self.action_type, self.server_name)
        self._goal = goal
        self._goal_future = client.send_goal_async(goal)
        self._timing = self.ros.start_timed(self._goal_future)  # server_timeout counts sim time, not DDS's
        self._phase = _Phase.SENT

    # -- StatefulActionNode --------------------------------------------------------------------------
    def on_start(self) -> NodeStatus:
        self._handle = None
        self._result_future = None
        goal = self.make_goal()
        if goal is None:
            return NodeStatus.FAILURE
        self._goal = goal
        client = self.ros.action_client(self.action_type, self.server_name)
        if client.server_is_ready():
            self._send(goal)
        else:
            wait_ms = int(self.config.blackboard.get("wait_for_service_timeout", DEFAULT_WAIT_FOR_SERVICE_MS))
            self._deadline = self.ros.wall_clock() + wait_ms / 1000.0
            self._phase = _Phase.WAITING_FOR_SERVER
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        if self._phase is _Phase.WAITING_FOR_SERVER:
            if self.ros.action_client(self.action_type, self.server_name).server_is_ready():
                self._send(self._goal)
            elif self.ros.wall_clock() > self._deadline:
                return self._fail(f"action server '{self.server_name}' is not available")
            return NodeStatus.RUNNING
        if self._phase is _Phase.SENT:
            return self._check_acknowledged()
        replacement = self.updated_goal()
        if replacement is not None:
            self._send(replacement)
            return NodeStatus.RUNNING
        assert self._result_future is not None
        if not self._result_future.done():
            return NodeStatus.RUNNING
        return self._finish(self._result_future.result())

    def _check_acknowledged(self) -> NodeStatus:
        assert self._goal_future is not None
        if not self._goal_future.done():
            timeout_ms = int(self.get_input_or("server_timeout", DEFAULT_SERVER_TIMEOUT_MS))
            assert self._timing is not None
            if self.ros.waited_ms(self._timing) <= timeout_ms:
                return NodeStatus.RUNNING
            self._goal_future.add_done_callback(cancel_if_accepted)
            self._goal_future = None
            return self._fail(f"timed out after {timeout_ms} ms waiting for action server "
                              f"'{self.server_name}' to acknowledge the goal request")
        handle = self._goal_future.result()
        self._goal_future = None
        if handle is None or not handle.accepted:
            return self._fail(f"the goal was rejected by '{self.server_name}'")
        self._handle = handle
        self._result_future = handle.get_result_async()
        self._phase = _Phase.ACTIVE
        return NodeStatus.RUNNING

    def _finish(self, response: Any) -> NodeStatus:
        self._handle = None
        self._result_future = None
        result = response.result
        code = int(getattr(result, "error_code", 0))
        if response.status == GoalStatus.STATUS_SUCCEEDED:
            self.set_output("error_code_id", 0)
            return self.on_success(result)
        if response.status == GoalStatus.STATUS_CANCELED:
            return NodeStatus.SUCCESS
        self.set_output("error_code_id", code)
        self.on_aborted(result)
        return self._fail(str(getattr(result, "error_msg", "")) or "the goal was aborted", code)

    def on_halted(self) -> None:
        if self._goal_future is not None:  # sent; acknowledged or not, the leaf has not looked yet
            self._goal_future.add_done_callback(cancel_if_accepted)
        elif self._handle is not None and self._result_future is not None and not self._result_future.done():
            self._handle.cancel_goal_async()
        self._goal_future = None
        self._handle = None
        self._result_future = None
