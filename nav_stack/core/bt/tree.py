"""A loaded behaviour tree and its tick-driven runner.

The caller owns time: ``tick_once(now)`` advances the tree by exactly one tick at time ``now``
(seconds; sim time under ROS, any monotonic number in tests). Nothing here sleeps, spawns threads
or reads the wall clock unless no ``now`` is given and the tree was built with a wall clock.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from nav_stack.core.bt.blackboard import Blackboard
from nav_stack.core.bt.node import StatusListener, TreeContext, TreeNode
from nav_stack.core.bt.status import NodeStatus


class Tree:
    """A tree instance: root node, every node in uid order, root blackboard and shared context."""

    def __init__(self, root: TreeNode, nodes: list[TreeNode], blackboard: Blackboard, context: TreeContext,
                 tree_id: str, source: str, clock: Callable[[], float] | None = None) -> None:
        self.root = root
        self.nodes = nodes
        self.blackboard = blackboard
        self.context = context
        self.tree_id = tree_id
        self.source = source
        self._clock = clock
        self._status = NodeStatus.IDLE
        self.tick_count = 0

    @property
    def status(self) -> NodeStatus:
        """Result of the last tick (IDLE before the first tick and after ``halt``)."""
        return self._status

    @property
    def now(self) -> float:
        """Time of the last tick in seconds."""
        return self.context.now

    def tick_once(self, now: float | None = None) -> NodeStatus:
        """Tick the root once at time ``now`` (seconds) and return its status.

        Raises:
            ValueError: ``now`` omitted and the tree has no clock.
        """
        if now is None:
            if self._clock is None:
                raise ValueError(f"tree '{self.tree_id}' ({self.source}) has no clock: pass now=")
            now = self._clock()
        self.context.now = float(now)
        self.tick_count += 1
        status = self.root.execute_tick()
        if status.is_completed:
            # BT.CPP Tree::tickRoot: a finished root starts over on the next tick.
            self.root.reset_status()
        self._status = status
        return status

    def halt(self) -> None:
        """Halt every RUNNING node (asynchronous leaves get ``on_halted``) and reset the tree."""
        self.root.halt_node()
        for node in self.nodes:
            node.halt_node()
        self.root.reset_status()
        self._status = NodeStatus.IDLE

    def add_status_listener(self, listener: StatusListener) -> None:
        """Call ``listener(node, previous, new)`` on every node status change."""
        self.context.status_listeners.append(listener)

    def find(self, name: str) -> list[TreeNode]:
        """Nodes whose instance name is ``name``."""
        return [node for node in self.nodes if node.name == name]

    def __iter__(self) -> Iterator[TreeNode]:
        return iter(self.nodes)
