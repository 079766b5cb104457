"""Node registry and tree factory (BT.CPP ``BehaviorTreeFactory``).

    factory = BehaviorTreeFactory()                  # BT.CPP built-ins + Nav2 core nodes
    factory.register("GoToPose", GoToPoseNode, navigator=client)   # extra kwargs go to __init__
    tree = factory.create_tree_from_file("config/trees/x.xml", clock=node_clock)

Registration records each type's ports (``provided_ports``) so the loader can check every XML
attribute, fill defaults and reject missing required ports before the first tick.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from nav_stack.core.bt import controls, decorators, leaves, nav2_conditions, nav2_controls
from nav_stack.core.bt.blackboard import Blackboard
from nav_stack.core.bt.builder import TreeBuilder
from nav_stack.core.bt.node import NodeConfig, SelectionSource, TreeContext, TreeNode
from nav_stack.core.bt.ports import PortInfo
from nav_stack.core.bt.tree import Tree
from nav_stack.core.bt.xml_model import XmlElement, parse_xml_file, parse_xml_text

RESERVED_IDS = frozenset({"root", "BehaviorTree", "TreeNodesModel", "include", "SubTree", "SubTreePlus",
                          "Action", "Condition", "Control", "Decorator"})
RESERVED_PORTS = frozenset({"name", "ID"})

BUILTIN_NODES: dict[str, type[TreeNode]] = {
    "Sequence": controls.Sequence,
    "SequenceWithMemory": controls.SequenceWithMemory,
    "Fallback": controls.Fallback,
    "ReactiveSequence": controls.ReactiveSequence,
    "ReactiveFallback": controls.ReactiveFallback,
    "Parallel": controls.Parallel,
    "Inverter": decorators.Inverter,
    "ForceSuccess": decorators.ForceSuccess,
    "ForceFailure": decorators.ForceFailure,
    "KeepRunningUntilFailure": decorators.KeepRunningUntilFailure,
    "RetryUntilSuccessful": decorators.RetryUntilSuccessful,
    "Repeat": decorators.Repeat,
    "Timeout": decorators.Timeout,
    "Delay": decorators.Delay,
    "AlwaysSuccess": leaves.AlwaysSuccess,
    "AlwaysFailure": leaves.AlwaysFailure,
    "Sleep": leaves.Sleep,
    "SetBlackboard": leaves.SetBlackboard,
}

NAV2_NODES: dict[str, type[TreeNode]] = {
    "PipelineSequence": nav2_controls.PipelineSequence,
    "RecoveryNode": nav2_controls.RecoveryNode,
    "RoundRobin": nav2_controls.RoundRobin,
    "RateController": nav2_controls.RateController,
    "GoalUpdated": nav2_conditions.GoalUpdated,
    "AreErrorCodesPresent": nav2_conditions.AreErrorCodesPresent,
    "WouldAPlannerRecoveryHelp": nav2_conditions.WouldAPlannerRecoveryHelp,
    "WouldAControllerRecoveryHelp": nav2_conditions.WouldAControllerRecoveryHelp,
    "PlannerSelector": nav2_conditions.PlannerSelector,
    "ControllerSelector": nav2_conditions.ControllerSelector,
    "GoalCheckerSelector": nav2_conditions.GoalCheckerSelector,
    "ProgressCheckerSelector": nav2_conditions.ProgressCheckerSelector,
}


@dataclass(frozen=True)
class NodeRegistration:
    """A registered node type: its class, extra constructor arguments and declared ports."""

    node_id: str
    node_type: type[TreeNode]
    kwargs: Mapping[str, Any] = field(default_factory=dict)
    manifest: Mapping[str, PortInfo] = field(default_factory=dict)

    def create(self, name: str, config: NodeConfig) -> TreeNode:
        """Instantiate the node with the registered extra arguments."""
        return self.node_type(name, config, **self.kwargs)


class BehaviorTreeFactory:
    """Registry of node types and loader of BT.CPP XML into ``Tree`` objects."""

    def __init__(self, *, builtins: bool = True, nav2: bool = True) -> None:
        self._registry: dict[str, NodeRegistration] = {}
        if builtins:
            for node_id, node_type in BUILTIN_NODES.items():
                self.register(node_id, node_type)
        if nav2:
            for node_id, node_type in NAV2_NODES.items():
                self.register(node_id, node_type)

    def register(self, node_id: str, node_type: type[TreeNode], **kwargs: Any) -> None:
        """Register ``node_type`` under ``node_id``; ``kwargs`` are passed to every instance.

        Raises:
            ValueError: empty, reserved or already registered id; not a TreeNode subclass;
                duplicate or reserved port names.
        """
        if not node_id or node_id in RESERVED_IDS:
            raise ValueError(f"cannot register node id '{node_id}': empty or reserved")
        if node_id in self._registry:
            raise ValueError(f"node id '{node_id}' is already registered "
                             f"(as {self._registry[node_id].node_type.__name__})")
        if not (isinstance(node_type, type) and issubclass(node_type, TreeNode)):
            raise ValueError(f"node id '{node_id}': {node_type!r} is not a TreeNode subclass")
        manifest: dict[str, PortInfo] = {}
        for port in node_type.provided_ports():
            if port.name in manifest or port.name in RESERVED_PORTS or port.name.startswith("_"):
                raise ValueError(f"node id '{node_id}': port name '{port.name}' is duplicated or reserved")
            manifest[port.name] = port
        self._registry[node_id] = NodeRegistration(node_id, node_type, dict(kwargs), manifest)

    def unregister(self, node_id: str) -> None:
        """Forget ``node_id`` (so it can be registered again with another class)."""
        self._registry.pop(node_id, None)

    def registration(self, node_id: str) -> NodeRegistration | None:
        """The registration of ``node_id``, or None."""
        return self._registry.get(node_id)

    def create_tree_from_text(self, text: str, *, source: str = "<string>", main_tree_id: str | None = None,
                              blackboard: Blackboard | None = None, clock: Callable[[], float] | None = None,
                              selection_source: SelectionSource | None = None) -> Tree:
        """Load XML text (``<include>`` paths resolve against the current directory)."""
        root = parse_xml_text(text, source)
        return self._create(root, Path.cwd(), main_tree_id, blackboard, clock, selection_source)

    def create_tree_from_file(self, path: str | Path, *, main_tree_id: str | None = None,
                              blackboard: Blackboard | None = None, clock: Callable[[], float] | None = None,
                              selection_source: SelectionSource | None = None) -> Tree:
        """Load an XML file (``<include>`` paths resolve against its folder)."""
        root = parse_xml_file(path)
        return self._create(root, Path(path).resolve().parent, main_tree_id, blackboard, clock,
                            selection_source)

    def _create(self, root: XmlElement, base_dir: Path, main_tree_id: str | None,
                blackboard: Blackboard | None, clock: Callable[[], float] | None,
                selection_source: SelectionSource | None) -> Tree:
        context = TreeContext(selection_source=selection_source)
        board = blackboard if blackboard is not None else Blackboard(name="root")
        return TreeBuilder(self._registry, context).build(root, base_dir, main_tree_id, board, clock)
