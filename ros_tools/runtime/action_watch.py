"""Notice that the action server running a goal is gone, so a client does not wait for ever for its result.

Why: an action client learns a goal's end only from the server's result. When the server's process
dies (a crash, a SIGKILL, a respawn by nav2_bringup's ``use_respawn``) no result ever comes, and rclpy
(like rclcpp_action and nav2_simple_commander) keeps waiting. DDS does not say it either: a killed
participant stays in the graph until its lease runs out (about 20 s with Fast DDS's defaults,
measured here), and a respawned server takes the same names meanwhile.

How, with what any ROS 2 action server offers (nothing Nav2-specific, nothing process-local):

* the graph: the status publishers of ``<action>/_action/status`` are the servers. A goal is watched
  against the set present when it is watched. While that set is unchanged nothing is sent;
* the result service as a probe: once the set changed (a server left or a new one appeared), the
  client asks ``<action>/_action/get_result`` for the goal again. A server that has the goal answers
  only when the goal ends; a server that does not know it answers at once with STATUS_UNKNOWN (rclpy's
  and rclcpp_action's behaviour for an unknown goal id): the server that accepted the goal is gone;
* no server at all in the graph for ABSENT_LIMIT_S: gone too (a lease that ran out, no respawn).

A frozen server (SIGSTOP) that is still in the graph is not "lost": it answers nothing and keeps its
goal, and may come back. Everything runs on a steady-clock timer of the node's executor: nothing
blocks, and it works whether or not sim time runs (a lockstep simulator holds sim time while a stack
process is gone).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from action_msgs.msg import GoalStatus
from rclpy.node import Node

from ros_tools.runtime.waiting import steady_clock

PROBE_PERIOD_S = 0.5  # wall s between two looks at the graph (and two probes while it differs)
ABSENT_LIMIT_S = 2.0  # wall s with no server at all in the graph before the goal counts as lost


class ServerLossWatch:
    """Watches goals of one action (``action_type`` on ``action_name``) for the loss of their server."""

    def __init__(self, node: Node, action_type: Any, action_name: str,
                 period_s: float = PROBE_PERIOD_S, absent_limit_s: float = ABSENT_LIMIT_S) -> None:
        self.node = node
        self.action_name = action_name
        self._request_type = action_type.Impl.GetResultService.Request
        self._probe = node.create_client(action_type.Impl.GetResultService,
                                         f"{action_name}/_action/get_result")
        self._status_topic = f"{action_name}/_action/status"
        self.period_s, self.absent_limit_s = period_s, absent_limit_s

    def servers(self) -> frozenset[bytes]:
        """The GIDs of the servers of the action in the graph now."""
        return frozenset(bytes(info.endpoint_gid) for info in
                         self.node.get_publishers_info_by_topic(self._status_topic))

    def watch(self, goal_id: Any, on_lost: Callable[[str], None]) -> Callable[[], None]:
        """Call ``on_lost(why)`` once (on the executor) if the server of goal ``goal_id`` (a
        unique_identifier_msgs/UUID) is gone; the returned function stops watching (call it when the
        result arrived)."""
        known = self.servers()
        state: dict[str, Any] = {"absent": 0.0, "probe": None, "done": False}

        def stop() -> None:
            if not state["done"]:
                state["done"] = True
                self.node.destroy_timer(timer)
                if state["probe"] is not None and not state["probe"].done():
                    self._probe.remove_pending_request(state["probe"])

        def lost(why: str) -> None:
            if not state["done"]:
                stop()
                on_lost(why)

        def on_answer(future: Any) -> None:
            response = future.result() if future.exception() is None else None
            if response is not None and response.status == GoalStatus.STATUS_UNKNOWN:
                lost(f"the '{self.action_name}' server that accepted the goal is gone (a new server "
                     "does not know the goal)")

        def look() -> None:
            if state["done"]:
                return
            now = self.servers()
            if not now:
                state["absent"] += self.period_s
                if state["absent"] >= self.absent_limit_s:
                    lost(f"no '{self.action_name}' server in the ROS graph for {self.absent_limit_s:g} s")
                return
            state["absent"] = 0.0
            if now == known or not self._probe.service_is_ready():
                return
            previous = state["probe"]
            if previous is not None and not previous.done():
                self._probe.remove_pending_request(previous)  # unanswered: the request may be lost
            state["probe"] = self._probe.call_async(self._request_type(goal_id=goal_id))
            state["probe"].add_done_callback(on_answer)

        timer = self.node.create_timer(self.period_s, look, clock=steady_clock())
        return stop

    def destroy(self) -> None:
        self.node.destroy_client(self._probe)
