"""Node base classes: the BT.CPP 4 node lifecycle in Python.

``execute_tick`` wraps a node's ``tick`` and records the returned status (SKIPPED leaves the node
IDLE); ``halt`` stops a RUNNING node and makes it IDLE. Parents reset or halt their children the
way BT.CPP's ``ControlNode``/``DecoratorNode`` do, so a halted subtree always ends IDLE and
asynchronous leaves get ``on_halted`` exactly once.

Subclass one of: ``SyncActionNode`` / ``ConditionNode`` (finish within the tick),
``StatefulActionNode`` (asynchronous: ``on_start`` / ``on_running`` / ``on_halted``, never blocks),
``ControlNode`` (children) or ``DecoratorNode`` (one child). Constructors take ``(name, config)``
plus any keyword arguments given to ``BehaviorTreeFactory.register``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

from nav_stack.core.bt.blackboard import Blackboard
from nav_stack.core.bt.errors import BtPortError, BtRuntimeError
from nav_stack.core.bt.ports import PortDirection, PortInfo, PortList, blackboard_key
from nav_stack.core.bt.status import NodeKind, NodeStatus

StatusListener = Callable[["TreeNode", NodeStatus, NodeStatus], None]
SelectionSource = Callable[[str], "str | None"]


@dataclass
class TreeContext:
    """State shared by all nodes of one tree: the clock and injected collaborators.

    Attributes:
        now: time of the current tick in seconds (sim or wall time, set by ``Tree.tick_once``).
        selection_source: topic name → latest selection (planner/controller/... id) or None; the
            ROS layer feeds it from subscriptions. Without it selectors read the root blackboard.
        status_listeners: called as ``listener(node, previous, new)`` on every status change.
    """

    now: float = 0.0
    selection_source: SelectionSource | None = None
    status_listeners: list[StatusListener] = field(default_factory=list)


@dataclass
class NodeConfig:
    """Everything the loader gives a node (``BT::NodeConfig``).

    Attributes:
        blackboard: the scope the node's ``{key}`` ports resolve in.
        ports: port name → raw value: the XML attribute string, or a declared default.
        manifest: port name → declaration, from the class's ``provided_ports``.
        context: the tree-wide context (clock, selection source, listeners).
        registration_id: the ID the node was created from (e.g. ``Sequence``).
        uid: unique id in the tree, depth-first from 1.
        path: ``MainTree/Fallback/Sequence::3`` style location for messages.
        source: ``file:line`` of the XML element, for runtime error messages.
    """

    blackboard: Blackboard
    ports: dict[str, Any] = field(default_factory=dict)
    manifest: dict[str, PortInfo] = field(default_factory=dict)
    context: TreeContext = field(default_factory=TreeContext)
    registration_id: str = ""
    uid: int = 0
    path: str = ""
    source: str = ""


class TreeNode:
    """Base of every node; subclasses implement ``tick`` (and ``halt`` when they keep state)."""

    kind: ClassVar[NodeKind] = NodeKind.ACTION

    def __init__(self, name: str, config: NodeConfig) -> None:
        self.name = name
        self.config = config
        self.parent: TreeNode | None = None
        self._status = NodeStatus.IDLE

    @classmethod
    def provided_ports(cls) -> PortList:
        """Ports this node type accepts (BT.CPP ``providedPorts``); none by default."""
        return ()

    # ------------------------------------------------------------------ status and lifecycle
    @property
    def status(self) -> NodeStatus:
        """Status recorded after the last tick, halt or reset."""
        return self._status

    @property
    def uid(self) -> int:
        """Unique id in the tree (depth-first order from 1)."""
        return self.config.uid

    @property
    def registration_id(self) -> str:
        """Type ID used in the XML."""
        return self.config.registration_id

    def children_nodes(self) -> list[TreeNode]:
        """Direct children (none for leaves)."""
        return []

    def set_status(self, status: NodeStatus) -> None:
        """Record ``status`` and notify listeners if it changed."""
        previous = self._status
        if previous is status:
            return
        self._status = status
        for listener in self.config.context.status_listeners:
            listener(self, previous, status)

    def reset_status(self) -> None:
        """Back to IDLE without calling ``halt`` (BT.CPP ``resetStatus``)."""
        self.set_status(NodeStatus.IDLE)

    def execute_tick(self) -> NodeStatus:
        """Tick once and record the result.

        SKIPPED is passed to the parent while the node itself goes back to IDLE (BT.CPP's stated
        intent; BT.CPP leaves a control node that set itself RUNNING before all its children
        skipped in RUNNING, which no parent can observe as different).
        """
        new_status = self.tick()
        if new_status is NodeStatus.IDLE:
            raise BtRuntimeError(f"{self.config.path} ({self.config.source}): tick() returned IDLE")
        self.set_status(NodeStatus.IDLE if new_status is NodeStatus.SKIPPED else new_status)
        return new_status

    def tick(self) -> NodeStatus:
        """One step of the node's work; must not block."""
        raise NotImplementedError(f"{type(self).__name__}.tick")

    def halt(self) -> None:
        """Stop a RUNNING node and return it to IDLE; leaves with no state just reset."""
        self.reset_status()

    def halt_node(self) -> None:
        """Entry point used by parents (BT.CPP ``haltNode``)."""
        self.halt()

    def now(self) -> float:
        """Time of the current tick in seconds."""
        return self.config.context.now

    # ------------------------------------------------------------------ ports
    def raw_port(self, name: str) -> Any:
        """The raw XML/default value of port ``name`` (None when absent)."""
        return self.config.ports.get(name)

    def get_input(self, name: str) -> Any:
        """Value of input port ``name``: a converted literal or the blackboard entry it points to.

        Raises:
            BtPortError: port not declared, not given and without default, missing blackboard
                entry, or a blackboard string that does not convert to the port's type.
        """
        info = self.config.manifest.get(name)
        if info is None or info.direction is PortDirection.OUTPUT:
            raise BtPortError(f"{self.config.path}: '{name}' is not an input port of {self.registration_id}")
        if name not in self.config.ports:
            raise BtPortError(f"{self.config.path}: input port '{name}' was not set in the XML")
        raw = self.config.ports[name]
        if not isinstance(raw, str):
            return raw
        key = blackboard_key(raw)
        if key is None:
            return _convert(info, raw, self.config.path)
        key = name if key == "=" else key
        try:
            value = self.config.blackboard.get(key)
        except KeyError as exc:
            raise BtPortError(f"{self.config.path}: input port '{name}': {exc.args[0]}") from None
        if isinstance(value, str) and info.type_ is not str and info.type_ is not object:
            return _convert(info, value, self.config.path)
        return value

    def get_input_or(self, name: str, fallback: Any) -> Any:
        """Like ``get_input`` but returns ``fallback`` when the value is unavailable."""
        try:
            return self.get_input(name)
        except BtPortError:
            return fallback

    def set_output(self, name: str, value: Any) -> bool:
        """Write ``value`` through output port ``name``; False when the XML did not wire the port.

        As in BT.CPP, ``{key}`` writes ``key``, ``{=}`` writes the port's own name and a plain
        string writes the key of that name.
        """
        info = self.config.manifest.get(name)
        if info is None or info.direction is PortDirection.INPUT:
            raise BtPortError(f"{self.config.path}: '{name}' is not an output port of {self.registration_id}")
        raw = self.config.ports.get(name)
        if not isinstance(raw, str) or not raw:
            return False
        key = blackboard_key(raw)
        key = raw if key is None else key
        self.config.blackboard.set(name if key == "=" else key, value)
        return True


def _convert(info: PortInfo, text: str, path: str) -> Any:
    try:
        return info.convert(text)
    except ValueError as exc:
        raise BtPortError(f"{path}: port '{info.name}': {exc}") from None


class SyncActionNode(TreeNode):
    """An action that finishes within one tick (returns SUCCESS or FAILURE, never RUNNING)."""

    kind = NodeKind.ACTION

    def execute_tick(self) -> NodeStatus:
        status = super().execute_tick()
        if status is NodeStatus.RUNNING:
            raise BtRuntimeError(f"{self.config.path}: a synchronous action must not return RUNNING")
        return status


class ConditionNode(SyncActionNode):
    """A check with no side effects; SUCCESS or FAILURE within the tick."""

    kind = NodeKind.CONDITION


class StatefulActionNode(TreeNode):
    """Base for asynchronous leaves (BT.CPP ``StatefulActionNode``).

    ``on_start`` runs on the tick that finds the node IDLE, ``on_running`` on later ticks while it
    is RUNNING, ``on_halted`` when a parent halts it while RUNNING. None of them may block: start
    the work (send an action goal, arm a timer) and report RUNNING until it is done.
    """

    kind = NodeKind.ACTION

    def on_start(self) -> NodeStatus:
        """Begin the work; return RUNNING, or SUCCESS/FAILURE if it finished at once."""
        raise NotImplementedError(f"{type(self).__name__}.on_start")

    def on_running(self) -> NodeStatus:
        """Poll the work started by ``on_start``."""
        raise NotImplementedError(f"{type(self).__name__}.on_running")

    def on_halted(self) -> None:
        """Cancel the work (e.g. cancel the action goal); called only while RUNNING."""

    def tick(self) -> NodeStatus:
        previous = self.status
        if previous is NodeStatus.IDLE:
            new_status = self.on_start()
        elif previous is NodeStatus.RUNNING:
            new_status = self.on_running()
        else:
            return previous
        if new_status is NodeStatus.IDLE:
            raise BtRuntimeError(f"{self.config.path}: on_start/on_running must not return IDLE")
        return new_status

    def halt(self) -> None:
        if self.status is NodeStatus.RUNNING:
            self.on_halted()
        self.reset_status()


class ControlNode(TreeNode):
    """A node with one or more children (BT.CPP ``ControlNode``)."""

    kind = NodeKind.CONTROL
    min_children: ClassVar[int] = 1
    max_children: ClassVar[int | None] = None

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self.children: list[TreeNode] = []

    def children_nodes(self) -> list[TreeNode]:
        return self.children

    def halt_child(self, index: int) -> None:
        """Halt child ``index`` if RUNNING, then reset it to IDLE."""
        child = self.children[index]
        if child.status is NodeStatus.RUNNING:
            child.halt_node()
        child.reset_status()

    def halt_children(self) -> None:
        """``halt_child`` for every child."""
        for index in range(len(self.children)):
            self.halt_child(index)

    def reset_children(self) -> None:
        """Same as ``halt_children`` (BT.CPP keeps both names)."""
        self.halt_children()

    def halt(self) -> None:
        self.reset_children()
        self.reset_status()


class DecoratorNode(TreeNode):
    """A node with exactly one child (BT.CPP ``DecoratorNode``)."""

    kind = NodeKind.DECORATOR

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._child: TreeNode | None = None

    @property
    def child(self) -> TreeNode:
        """The decorated node."""
        if self._child is None:
            raise BtRuntimeError(f"{self.config.path}: decorator has no child")
        return self._child

    def set_child(self, child: TreeNode) -> None:
        """Attach the decorated node (done by the loader)."""
        self._child = child

    def children_nodes(self) -> list[TreeNode]:
        return [] if self._child is None else [self._child]

    def reset_child(self) -> None:
        """Halt the child if RUNNING, then reset it to IDLE."""
        child = self.child
        if child.status is NodeStatus.RUNNING:
            child.halt_node()
        child.reset_status()

    def halt(self) -> None:
        self.reset_child()
        self.reset_status()
