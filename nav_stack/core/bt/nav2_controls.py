"""Nav2's control and decorator nodes (nav2_behavior_tree, Jazzy), on the BT.CPP 4 base classes.

* ``PipelineSequence``: re-ticks the children before the RUNNING one on every tick (so the planner
  under a RateController keeps replanning while the controller runs); fails on any FAILURE.
* ``RecoveryNode``: child 1 is the action, child 2 the recovery; on failure it runs the recovery
  and retries the action, at most ``number_of_retries`` times, within the same tick.
* ``RoundRobin``: tries one child per call, keeping (and wrapping) its index across ticks so each
  call starts with the next recovery; SUCCESS on the first child that succeeds.
* ``RateController``: ticks its child at most ``hz`` times per second of tree time, but every tick
  while the child is RUNNING; RUNNING in between.
"""

from __future__ import annotations

from nav_stack.core.bt.errors import BtRuntimeError
from nav_stack.core.bt.node import ControlNode, DecoratorNode, NodeConfig
from nav_stack.core.bt.ports import PortList, input_port
from nav_stack.core.bt.status import NodeStatus


class PipelineSequence(ControlNode):
    """Sequence that re-ticks earlier children while a later child runs."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.last_child_ticked = 0

    def tick(self) -> NodeStatus:
        for index, child in enumerate(self.children):
            child_status = child.execute_tick()
            if child_status is NodeStatus.FAILURE:
                self.halt_children()
                self.last_child_ticked = 0
                return NodeStatus.FAILURE
            if child_status is NodeStatus.RUNNING and index >= self.last_child_ticked:
                self.last_child_ticked = index
                return NodeStatus.RUNNING
            if child_status is NodeStatus.IDLE:
                raise BtRuntimeError(f"{self.config.path}: a child returned IDLE")
        self.halt_children()
        self.last_child_ticked = 0
        return NodeStatus.SUCCESS

    def halt(self) -> None:
        self.last_child_ticked = 0
        super().halt()


class RecoveryNode(ControlNode):
    """Action + recovery pair retried up to ``number_of_retries`` times."""

    min_children = 2
    max_children = 2

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.current_child_idx = 0
        self.retry_count = 0

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("number_of_retries", int, 1, "recoveries before giving up"),)

    def tick(self) -> NodeStatus:
        retries = int(self.get_input("number_of_retries"))
        self.set_status(NodeStatus.RUNNING)
        while self.current_child_idx < 2 and self.retry_count <= retries:
            child_status = self.children[self.current_child_idx].execute_tick()
            if child_status is NodeStatus.RUNNING:
                return NodeStatus.RUNNING
            if child_status is NodeStatus.IDLE:
                raise BtRuntimeError(f"{self.config.path}: a child returned IDLE")
            if self.current_child_idx == 0:
                if child_status is NodeStatus.FAILURE and self.retry_count < retries:
                    self.halt_child(0)
                    self.current_child_idx = 1
                    continue
                if child_status is NodeStatus.SUCCESS:
                    self.halt_child(1)
                self.halt()
                return child_status  # SUCCESS, SKIPPED, or FAILURE with retries used up
            if child_status is NodeStatus.SKIPPED:
                self.current_child_idx = 0
                self.halt_child(1)
                return NodeStatus.FAILURE
            if child_status is NodeStatus.FAILURE:
                self.halt()
                return NodeStatus.FAILURE
            self.halt_child(1)
            self.retry_count += 1
            self.current_child_idx = 0
        self.halt()
        return NodeStatus.FAILURE

    def halt(self) -> None:
        super().halt()
        self.retry_count = 0
        self.current_child_idx = 0


class RoundRobin(ControlNode):
    """One child per attempt, continuing from where the last call stopped."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.current_child_idx = 0
        self.num_failed_children = 0

    def tick(self) -> NodeStatus:
        count = len(self.children)
        self.set_status(NodeStatus.RUNNING)
        skipped = 0
        while self.num_failed_children + skipped < count:
            child_status = self.children[self.current_child_idx].execute_tick()
            if child_status is not NodeStatus.RUNNING:
                self.current_child_idx = (self.current_child_idx + 1) % count
            if child_status is NodeStatus.SUCCESS:
                self.num_failed_children = 0
                self.halt_children()
                return NodeStatus.SUCCESS
            if child_status is NodeStatus.RUNNING:
                return NodeStatus.RUNNING
            if child_status is NodeStatus.FAILURE:
                self.num_failed_children += 1
            elif child_status is NodeStatus.SKIPPED:
                skipped += 1
            else:
                raise BtRuntimeError(f"{self.config.path}: a child returned IDLE")
        self.halt()
        return NodeStatus.SKIPPED if skipped == count else NodeStatus.FAILURE

    def halt(self) -> None:
        super().halt()
        self.current_child_idx = 0
        self.num_failed_children = 0


class RateController(DecoratorNode):
    """Throttle the child to ``hz`` (tree time); keep ticking it while it is RUNNING."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._start = 0.0
        self._first_time = False

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("hz", float, 10.0, "rate in Hz"),)

    def tick(self) -> NodeStatus:
        hz = float(self.get_input("hz"))
        if hz <= 0.0:
            raise BtRuntimeError(f"{self.config.path}: hz must be positive, got {hz}")
        if not self.status.is_active:
            self._start = self.now()
            self._first_time = True
        self.set_status(NodeStatus.RUNNING)
        if (self._first_time or self.child.status is NodeStatus.RUNNING
                or self.now() - self._start >= 1.0 / hz):
            self._first_time = False
            child_status = self.child.execute_tick()
            if child_status is NodeStatus.SUCCESS:
                self._start = self.now()
            return child_status
        return NodeStatus.RUNNING
