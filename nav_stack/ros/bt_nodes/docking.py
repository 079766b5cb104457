"""The docking BT leaves of opennav_docking_bt (Nav2 Jazzy): DockRobot and UndockRobot.

Ports are Nav2's. DockRobot: ``use_dock_id`` (true), ``dock_id``, ``dock_pose`` (PoseStamped),
``dock_type``, ``max_staging_time`` (1000 s), ``navigate_to_staging_pose`` (true); outputs ``success``,
``num_retries``, ``error_code_id`` and ``error_msg``. UndockRobot: ``dock_type``, ``max_undocking_time``
(30 s); outputs ``success``, ``error_code_id``, ``error_msg``. As Nav2's leaf does, DockRobot reads
``dock_pose``, ``dock_type`` and ``max_staging_time`` only when ``use_dock_id`` is false (with a dock id
the goal keeps the message's 1000 s). Success and abort both write ``success`` (and ``num_retries``);
a cancelled goal is SUCCESS with no outputs but ``error_code_id`` 0, as Nav2's ``on_cancelled``.
"""

from __future__ import annotations

from typing import Any

from nav2_msgs.action import DockRobot, UndockRobot

from nav_stack.core.bt import PortList, input_port, output_port
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.action_node import BtActionNode


class _DockingAction(BtActionNode):
    """Writes the result's ``success`` (and ``num_retries`` when it has one) on success and abort."""

    def on_success(self, result: Any) -> NodeStatus:
        self._write_outputs(result)
        self.set_output("error_msg", "")
        return NodeStatus.SUCCESS

    def _write_outputs(self, result: Any) -> None:
        self.set_output("success", bool(result.success))
        if hasattr(result, "num_retries"):
            self.set_output("num_retries", int(result.num_retries))

    def on_aborted(self, result: Any) -> None:
        self._write_outputs(result)
        self.set_output("error_msg", str(result.error_msg))

    @classmethod
    def result_ports(cls) -> PortList:
        return (output_port("success", bool, description="whether the action succeeded"),
                output_port("error_msg", str, description="the server's error message"))


class DockRobotAction(_DockingAction):
    """Dock at ``dock_id`` (or at ``dock_pose`` of ``dock_type``)."""

    action_type = DockRobot
    default_server_name = "dock_robot"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(), *cls.result_ports(),
                input_port("use_dock_id", bool, True, "use dock_id (else dock_pose and dock_type)"),
                input_port("dock_id", str, description="dock name in the dock database"),
                input_port("dock_pose", object, description="the dock (PoseStamped), if not using dock_id"),
                input_port("dock_type", str, description="the dock plugin, if using dock_pose"),
                input_port("max_staging_time", float, 1000.0, "s to navigate to the staging pose"),
                input_port("navigate_to_staging_pose", bool, True, "navigate to the staging pose first"),
                output_port("num_retries", int, description="the number of retries the docking took"))

    def make_goal(self) -> Any:
        goal = DockRobot.Goal()
        goal.use_dock_id = bool(self.get_input("use_dock_id"))
        if goal.use_dock_id:
            goal.dock_id = str(self.get_input_or("dock_id", ""))
        else:
            pose = self.get_input_or("dock_pose", None)
            if pose is not None:
                goal.dock_pose = pose
            goal.dock_type = str(self.get_input_or("dock_type", ""))
            goal.max_staging_time = float(self.get_input("max_staging_time"))
        goal.navigate_to_staging_pose = bool(self.get_input("navigate_to_staging_pose"))
        return goal


class UndockRobotAction(_DockingAction):
    """Undock from ``dock_type`` (empty: the dock the server docked at)."""

    action_type = UndockRobot
    default_server_name = "undock_robot"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(), *cls.result_ports(),
                input_port("dock_type", str, description="the dock plugin, if not the one docked at"),
                input_port("max_undocking_time", float, 30.0, "s to get back to the staging pose"))

    def make_goal(self) -> Any:
        goal = UndockRobot.Goal()
        goal.dock_type = str(self.get_input_or("dock_type", ""))
        goal.max_undocking_time = float(self.get_input("max_undocking_time"))
        return goal
