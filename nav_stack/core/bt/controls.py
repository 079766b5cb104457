"""The BT.CPP 4 control nodes: Sequence, SequenceWithMemory, Fallback, Reactive*, Parallel.

The differences that matter (BT.CPP 4.x semantics, reproduced exactly):

* ``Sequence`` / ``Fallback`` resume at the child that was RUNNING; earlier children are not
  ticked again until the node completes. A failing child resets a Sequence to its first child.
* ``SequenceWithMemory`` keeps its index when a child fails (and when halted), so the next tick
  retries the failed child instead of starting over.
* ``ReactiveSequence`` / ``ReactiveFallback`` tick from the first child on every tick; when a
  child is RUNNING every other child is halted and reset to IDLE.
* ``Parallel`` ticks all unfinished children each tick and completes when ``success_count``
  children succeeded or ``failure_count`` failed (negative counts mean "all but n-1").
"""

from __future__ import annotations

from nav_stack.core.bt.errors import BtRuntimeError
from nav_stack.core.bt.node import ControlNode, NodeConfig
from nav_stack.core.bt.ports import PortList, input_port
from nav_stack.core.bt.status import NodeStatus


def _idle_error(node: ControlNode) -> BtRuntimeError:
    return BtRuntimeError(f"{node.config.path}: a child returned IDLE")


class _OrderedBase(ControlNode):
    """Shared loop of Sequence (stops on FAILURE) and Fallback (stops on SUCCESS): the children in
    order, resuming at a RUNNING child; all of them SKIPPED makes the node SKIPPED."""

    _stop_on: NodeStatus = NodeStatus.FAILURE
    _finish: NodeStatus = NodeStatus.SUCCESS

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.current_child_idx = 0
        self._skipped = 0

    def tick(self) -> NodeStatus:
        if not self.status.is_active:
            self._skipped = 0
        self.set_status(NodeStatus.RUNNING)
        count = len(self.children)
        while self.current_child_idx < count:
            child_status = self.children[self.current_child_idx].execute_tick()
            if child_status is NodeStatus.RUNNING:
                return NodeStatus.RUNNING
            if child_status is self._stop_on:
                self._on_stop()
                return self._stop_on
            if child_status is NodeStatus.SKIPPED:
                self._skipped += 1
            elif child_status is NodeStatus.IDLE:
                raise _idle_error(self)
            self.current_child_idx += 1
        all_skipped = self._skipped == count
        self.reset_children()
        self.current_child_idx = 0
        self._skipped = 0
        return NodeStatus.SKIPPED if all_skipped else self._finish

    def _on_stop(self) -> None:
        """A child ended the loop early: start again from the first child next time."""
        self.reset_children()
        self.current_child_idx = 0

    def halt(self) -> None:
        self.current_child_idx = 0
        self._skipped = 0
        super().halt()


class Sequence(_OrderedBase):
    """Tick children in order; fail on the first failure; resume at a RUNNING child."""


class SequenceWithMemory(Sequence):
    """A Sequence that keeps its place on failure and on halt (v3 name: ``SequenceStar``)."""

    def _on_stop(self) -> None:
        for index in range(self.current_child_idx, len(self.children)):
            self.halt_child(index)

    def halt(self) -> None:
        self._skipped = 0
        ControlNode.halt(self)


class Fallback(_OrderedBase):
    """Tick children in order until one succeeds; resume at a RUNNING child."""

    _stop_on = NodeStatus.SUCCESS
    _finish = NodeStatus.FAILURE


class _ReactiveBase(ControlNode):
    """Shared loop of ReactiveSequence (stops on FAILURE) and ReactiveFallback (stops on SUCCESS)."""

    _stop_on: NodeStatus = NodeStatus.FAILURE
    _finish: NodeStatus = NodeStatus.SUCCESS

    def tick(self) -> NodeStatus:
        all_skipped = True
        self.set_status(NodeStatus.RUNNING)
        for index, child in enumerate(self.children):
            child_status = child.execute_tick()
            all_skipped = all_skipped and child_status is NodeStatus.SKIPPED
            if child_status is NodeStatus.RUNNING:
                for other in range(len(self.children)):
                    if other != index:
                        self.halt_child(other)
                return NodeStatus.RUNNING
            if child_status is self._stop_on:
                self.reset_children()
                return child_status
            if child_status is NodeStatus.SKIPPED:
                self.halt_child(index)
            elif child_status is NodeStatus.IDLE:
                raise _idle_error(self)
        self.reset_children()
        return NodeStatus.SKIPPED if all_skipped else self._finish


class ReactiveSequence(_ReactiveBase):
    """Re-check every child from the first on each tick; fail as soon as one fails."""

    _stop_on = NodeStatus.FAILURE
    _finish = NodeStatus.SUCCESS


class ReactiveFallback(_ReactiveBase):
    """Re-check every child from the first on each tick; succeed as soon as one succeeds."""

    _stop_on = NodeStatus.SUCCESS
    _finish = NodeStatus.FAILURE


class Parallel(ControlNode):
    """Tick all unfinished children every tick; thresholds decide success and failure."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._completed: set[int] = set()
        self._successes = 0
        self._failures = 0

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("success_count", int, -1, "children that must succeed; -1 = all"),
            input_port("failure_count", int, 1, "children failing before the node fails; -1 = all"),
        )

    def _threshold(self, value: int) -> int:
        return max(len(self.children) + value + 1, 0) if value < 0 else value

    def tick(self) -> NodeStatus:
        success_setting = int(self.get_input("success_count"))
        need_success = self._threshold(success_setting)
        need_failure = self._threshold(int(self.get_input("failure_count")))
        count = len(self.children)
        if count < need_success or count < need_failure:
            raise BtRuntimeError(
                f"{self.config.path}: {count} children cannot meet success_count {need_success} "
                f"/ failure_count {need_failure}")
        self.set_status(NodeStatus.RUNNING)
        skipped = 0
        for index, child in enumerate(self.children):
            if index not in self._completed:
                child_status = child.execute_tick()
                if child_status is NodeStatus.SKIPPED:
                    skipped += 1
                elif child_status is NodeStatus.SUCCESS:
                    self._completed.add(index)
                    self._successes += 1
                elif child_status is NodeStatus.FAILURE:
                    self._completed.add(index)
                    self._failures += 1
                elif child_status is NodeStatus.IDLE:
                    raise _idle_error(self)
            if self._successes >= need_success or (
                    success_setting < 0 and self._successes + skipped >= need_success):
                self._finish()
                return NodeStatus.SUCCESS
            if count - self._failures < need_success or self._failures == need_failure:
                self._finish()
                return NodeStatus.FAILURE
        return NodeStatus.SKIPPED if skipped == count else NodeStatus.RUNNING

    def _finish(self) -> None:
        self._completed.clear()
        self._successes = 0
        self._failures = 0
        self.reset_children()

    def halt(self) -> None:
        self._completed.clear()
        self._successes = 0
        self._failures = 0
        super().halt()
