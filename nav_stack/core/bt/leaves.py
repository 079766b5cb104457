"""Built-in leaves of BT.CPP 4: AlwaysSuccess, AlwaysFailure, Sleep, SetBlackboard."""

from __future__ import annotations

from nav_stack.core.bt.node import NodeConfig, StatefulActionNode, SyncActionNode
from nav_stack.core.bt.ports import PortList, bidirectional_port, blackboard_key, input_port
from nav_stack.core.bt.status import NodeStatus


class AlwaysSuccess(SyncActionNode):
    """Returns SUCCESS."""

    def tick(self) -> NodeStatus:
        return NodeStatus.SUCCESS


class AlwaysFailure(SyncActionNode):
    """Returns FAILURE."""

    def tick(self) -> NodeStatus:
        return NodeStatus.FAILURE


class Sleep(StatefulActionNode):
    """RUNNING for ``msec`` milliseconds of tree time, then SUCCESS; never blocks the tick."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._wake_at = 0.0

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("msec", int, description="duration in milliseconds", required=True),)

    def on_start(self) -> NodeStatus:
        msec = int(self.get_input("msec"))
        if msec <= 0:
            return NodeStatus.SUCCESS
        self._wake_at = self.now() + msec / 1000.0
        return NodeStatus.RUNNING

    def on_running(self) -> NodeStatus:
        return NodeStatus.SUCCESS if self.now() >= self._wake_at else NodeStatus.RUNNING


class SetBlackboard(SyncActionNode):
    """Write ``value`` (a literal string, or a copy of the ``{key}`` entry) into ``output_key``."""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("value", str, description="literal or {key} to copy", required=True),
            bidirectional_port("output_key", object, description="key to write", required=True),
        )

    def tick(self) -> NodeStatus:
        raw_value = str(self.raw_port("value"))
        source_key = blackboard_key(raw_value)
        if source_key is None:
            value: object = raw_value
        elif source_key in self.config.blackboard:
            value = self.config.blackboard.get(source_key)
        else:
            return NodeStatus.FAILURE
        self.set_output("output_key", value)
        return NodeStatus.SUCCESS
