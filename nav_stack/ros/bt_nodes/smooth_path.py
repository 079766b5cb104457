"""The SmoothPath BT leaf of nav2_behavior_tree (Jazzy): send a path to the smoother server.

Ports are Nav2's: ``unsmoothed_path`` (nav_msgs/Path), ``smoother_id`` (""), ``max_smoothing_duration``
(3.0 s), ``check_for_collisions`` (false), server ``smooth_path``; outputs ``smoothed_path``,
``smoothing_duration`` (s), ``was_completed``, ``error_code_id`` and ``error_msg``. As Nav2's leaf does,
a success writes every output (``error_msg`` empty), an abort only the error code and message, and a
cancelled goal is SUCCESS. A tree usually smooths a plan in place: ``unsmoothed_path="{path}"
smoothed_path="{path}"``.
"""

from __future__ import annotations

import math
from typing import Any

from nav2_msgs.action import SmoothPath

from nav_stack.core.bt import PortList, input_port, output_port
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.action_node import BtActionNode
from nav_stack.ros.common.conversions import duration_msg, duration_to_seconds


class SmoothPathAction(BtActionNode):
    """Smooth ``unsmoothed_path``; writes ``smoothed_path``."""

    action_type = SmoothPath
    default_server_name = "smooth_path"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("unsmoothed_path", object, description="path to be smoothed (nav_msgs/Path)"),
                input_port("max_smoothing_duration", float, 3.0, "s the smoothing may take"),
                input_port("check_for_collisions", bool, False, "check the smoothed path for collisions"),
                input_port("smoother_id", str, "", "smoother plugin id"),
                output_port("smoothed_path", object, description="the smoothed path (nav_msgs/Path)"),
                output_port("smoothing_duration", float, description="s the smoothing took"),
                output_port("was_completed", bool, description="smoothing finished within its time limit"),
                output_port("error_msg", str, description="the smoother server's error message"))

    def make_goal(self) -> Any:
        seconds = float(self.get_input("max_smoothing_duration"))
        if not math.isfinite(seconds) or seconds < 0.0:
            self._fail(f"max_smoothing_duration must be a finite number of seconds >= 0, got {seconds}")
            return None
        goal = SmoothPath.Goal()
        path = self.get_input_or("unsmoothed_path", None)
        if path is not None:
            goal.path = path
        goal.smoother_id = str(self.get_input("smoother_id"))
        goal.max_smoothing_duration = duration_msg(seconds)
        goal.check_for_collisions = bool(self.get_input("check_for_collisions"))
        return goal

    def on_success(self, result: Any) -> NodeStatus:
        self.set_output("smoothed_path", result.path)
        self.set_output("smoothing_duration", duration_to_seconds(result.smoothing_duration))
        self.set_output("was_completed", bool(result.was_completed))
        self.set_output("error_msg", "")
        return NodeStatus.SUCCESS

    def on_aborted(self, result: Any) -> None:
        self.set_output("error_msg", str(result.error_msg))
