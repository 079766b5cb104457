"""The BT.CPP 4 decorators, plus the SubTree node.

Time-based decorators (Timeout, Delay) read the tree's clock (``TreeNode.now``, seconds) instead of
starting timer threads as BT.CPP does. A timer "fires" when a tick sees that its deadline has
passed, so in sim time they follow /clock and in tests they follow the injected ``now``.
Port units follow BT.CPP: milliseconds.
"""

from __future__ import annotations

from nav_stack.core.bt.errors import BtRuntimeError
from nav_stack.core.bt.node import DecoratorNode, NodeConfig
from nav_stack.core.bt.ports import PortList, input_port
from nav_stack.core.bt.status import NodeKind, NodeStatus


class Inverter(DecoratorNode):
    """SUCCESS ↔ FAILURE; RUNNING and SKIPPED pass through."""

    def tick(self) -> NodeStatus:
        self.set_status(NodeStatus.RUNNING)
        child_status = self.child.execute_tick()
        if child_status.is_completed:
            self.reset_child()
            return NodeStatus.FAILURE if child_status is NodeStatus.SUCCESS else NodeStatus.SUCCESS
        return child_status


class ForceSuccess(DecoratorNode):
    """A completed child always reports SUCCESS."""

    forced: NodeStatus = NodeStatus.SUCCESS

    def tick(self) -> NodeStatus:
        self.set_status(NodeStatus.RUNNING)
        child_status = self.child.execute_tick()
        if child_status.is_completed:
            self.reset_child()
            return self.forced
        return child_status


class ForceFailure(ForceSuccess):
    """A completed child always reports FAILURE."""

    forced = NodeStatus.FAILURE


class KeepRunningUntilFailure(DecoratorNode):
    """RUNNING while the child keeps succeeding (it is restarted); FAILURE when it fails."""

    def tick(self) -> NodeStatus:
        self.set_status(NodeStatus.RUNNING)
        child_status = self.child.execute_tick()
        if child_status is NodeStatus.FAILURE:
            self.reset_child()
            return NodeStatus.FAILURE
        if child_status is NodeStatus.SUCCESS:
            self.reset_child()
        return NodeStatus.RUNNING


class _LoopDecorator(DecoratorNode):
    """RetryUntilSuccessful and Repeat: loop the child within one tick until a stop outcome.

    ``_count_on`` is the outcome that restarts the child; the other completed outcome ends the loop.
    """

    _port: str = ""
    _count_on: NodeStatus = NodeStatus.FAILURE

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.count = 0
        self._all_skipped = True

    def tick(self) -> NodeStatus:
        limit = int(self.get_input(self._port))
        if self.status is NodeStatus.IDLE:
            self._all_skipped = True
        self.set_status(NodeStatus.RUNNING)
        looping = limit == -1 or self.count < limit
        while looping:
            child_status = self.child.execute_tick()
            self._all_skipped = self._all_skipped and child_status is NodeStatus.SKIPPED
            if child_status is NodeStatus.RUNNING:
                return NodeStatus.RUNNING
            if child_status is NodeStatus.SKIPPED:
                self.reset_child()
                return NodeStatus.SKIPPED
            if child_status is NodeStatus.IDLE:
                raise BtRuntimeError(f"{self.config.path}: the child returned IDLE")
            self.reset_child()
            if child_status is not self._count_on:
                self.count = 0
                return child_status
            self.count += 1
            looping = limit == -1 or self.count < limit
        self.count = 0
        return NodeStatus.SKIPPED if self._all_skipped else self._count_on

    def halt(self) -> None:
        self.count = 0
        super().halt()


class RetryUntilSuccessful(_LoopDecorator):
    """Restart a failing child up to ``num_attempts`` times (-1 = forever)."""

    _port = "num_attempts"
    _count_on = NodeStatus.FAILURE

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("num_attempts", int, description="attempts before failing; -1 = infinite",
                           required=True),)


class Repeat(_LoopDecorator):
    """Run a succeeding child ``num_cycles`` times (-1 = forever); stop on its first failure."""

    _port = "num_cycles"
    _count_on = NodeStatus.SUCCESS

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("num_cycles", int, description="repetitions; -1 = infinite", required=True),)


class Timeout(DecoratorNode):
    """Halt the child and fail if it is still RUNNING ``msec`` milliseconds after it started."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._deadline: float | None = None

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("msec", int, description="time limit in milliseconds", required=True),)

    def tick(self) -> NodeStatus:
        if self._deadline is None:
            msec = int(self.get_input("msec"))
            self.set_status(NodeStatus.RUNNING)
            self._deadline = self.now() + msec / 1000.0 if msec > 0 else float("inf")
        elif self.now() >= self._deadline and self.child.status is NodeStatus.RUNNING:
            self.reset_child()
            self._deadline = None
            return NodeStatus.FAILURE
        child_status = self.child.execute_tick()
        if child_status.is_completed:
            self._deadline = None
            self.reset_child()
        return child_status

    def halt(self) -> None:
        self._deadline = None
        super().halt()


class Delay(DecoratorNode):
    """Wait ``delay_msec`` milliseconds (RUNNING) before ticking the child for the first time."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._ready_at: float | None = None

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("delay_msec", int, description="delay in milliseconds", required=True),)

    def tick(self) -> NodeStatus:
        if self._ready_at is None:
            self.set_status(NodeStatus.RUNNING)
            self._ready_at = self.now() + int(self.get_input("delay_msec")) / 1000.0
        if self.now() < self._ready_at:
            return NodeStatus.RUNNING
        child_status = self.child.execute_tick()
        if child_status.is_completed:
            self._ready_at = None
            self.reset_child()
        return child_status

    def halt(self) -> None:
        self._ready_at = None
        super().halt()


class SubTreeNode(DecoratorNode):
    """Root of an instantiated ``<SubTree ID=...>``; its child is the subtree's root node.

    The subtree's own blackboard (with the port remappings) is in ``config.blackboard``.
    """

    kind = NodeKind.SUBTREE

    def __init__(self, name: str, config: NodeConfig, subtree_id: str = "") -> None:
        super().__init__(name, config)
        self.subtree_id = subtree_id

    def tick(self) -> NodeStatus:
        if self.status is NodeStatus.IDLE:
            self.set_status(NodeStatus.RUNNING)
        child_status = self.child.execute_tick()
        if child_status.is_completed:
            self.reset_child()
        return child_status
