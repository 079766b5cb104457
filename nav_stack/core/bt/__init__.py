"""Behaviour-tree engine for BehaviorTree.CPP 4 XML (and the v3 form), in pure Python.

Semantics follow BT.CPP 4 (controls, decorators, halting, SKIPPED) plus Nav2's control nodes,
so Nav2's default trees and the seed project's tree run unchanged. Time comes from the caller
(``Tree.tick_once(now)``); asynchronous leaves subclass ``StatefulActionNode``; ROS-specific leaves
are registered by the ROS layer with ``BehaviorTreeFactory.register``.

Why not built on py_trees: its composites differ from BT.CPP where it matters here (memory
flags instead of Sequence/ReactiveSequence semantics, no IDLE/SKIPPED, INVALID-on-stop instead of
BT.CPP's halt/reset contract, no ports), its blackboard is process-global and its Timeout reads the
wall clock, and ``*/core`` may import only stdlib/numpy. What it would have given (text/dot
rendering, snapshots) is the ~100 lines of ``export.py``.
"""

from nav_stack.core.bt.blackboard import Blackboard
from nav_stack.core.bt.errors import BtError, BtLoadError, BtPortError, BtRuntimeError
from nav_stack.core.bt.export import NodeSnapshot, ascii_tree, dot_tree, snapshot
from nav_stack.core.bt.factory import BehaviorTreeFactory, NodeRegistration
from nav_stack.core.bt.node import (
    ConditionNode,
    ControlNode,
    DecoratorNode,
    NodeConfig,
    StatefulActionNode,
    SyncActionNode,
    TreeContext,
    TreeNode,
)
from nav_stack.core.bt.ports import (
    PortDirection,
    PortInfo,
    PortList,
    bidirectional_port,
    input_port,
    output_port,
    semicolon_list,
)
from nav_stack.core.bt.status import NodeKind, NodeStatus
from nav_stack.core.bt.tree import Tree

__all__ = [
    "BehaviorTreeFactory",
    "Blackboard",
    "BtError",
    "BtLoadError",
    "BtPortError",
    "BtRuntimeError",
    "ConditionNode",
    "ControlNode",
    "DecoratorNode",
    "NodeConfig",
    "NodeKind",
    "NodeRegistration",
    "NodeSnapshot",
    "NodeStatus",
    "PortDirection",
    "PortInfo",
    "PortList",
    "StatefulActionNode",
    "SyncActionNode",
    "Tree",
    "TreeContext",
    "TreeNode",
    "ascii_tree",
    "bidirectional_port",
    "dot_tree",
    "input_port",
    "output_port",
    "semicolon_list",
    "snapshot",
]
