"""Views of a tree for people and viewers: indented text, Graphviz dot, and a status snapshot.

The snapshot is a flat list (uid, name, type, kind, status, parent uid) that the ROS layer can
publish every tick for a live viewer; ``ascii_tree`` and ``dot_tree`` render the same data.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from nav_stack.core.bt.node import TreeNode
from nav_stack.core.bt.status import NodeKind, NodeStatus
from nav_stack.core.bt.tree import Tree

_STATUS_COLOURS = {
    NodeStatus.IDLE: "white",
    NodeStatus.RUNNING: "orange",
    NodeStatus.SUCCESS: "palegreen",
    NodeStatus.FAILURE: "salmon",
    NodeStatus.SKIPPED: "lightgrey",
}
_KIND_SHAPES = {
    NodeKind.CONTROL: "box",
    NodeKind.DECORATOR: "hexagon",
    NodeKind.SUBTREE: "folder",
    NodeKind.ACTION: "ellipse",
    NodeKind.CONDITION: "diamond",
}


@dataclass(frozen=True)
class NodeSnapshot:
    """One node's state at one instant (``parent_uid`` 0 for the root)."""

    uid: int
    name: str
    type_id: str
    kind: str
    status: str
    parent_uid: int
    depth: int

    def as_dict(self) -> dict[str, Any]:
        """Plain dict for JSON/YAML serialisation."""
        return asdict(self)


def _walk(node: TreeNode, depth: int = 0) -> list[tuple[TreeNode, int]]:
    rows = [(node, depth)]
    for child in node.children_nodes():
        rows.extend(_walk(child, depth + 1))
    return rows


def _label(node: TreeNode) -> str:
    type_id = node.registration_id
    if node.kind is NodeKind.SUBTREE:
        type_id = f"SubTree[{getattr(node, 'subtree_id', '')}]"
    return type_id if node.name in (type_id, node.registration_id) else f'{type_id} "{node.name}"'


def snapshot(tree: Tree) -> list[NodeSnapshot]:
    """Every node, depth-first, with its current status."""
    return [
        NodeSnapshot(node.uid, node.name, node.registration_id, node.kind.value, node.status.value,
                     node.parent.uid if node.parent is not None else 0, depth)
        for node, depth in _walk(tree.root)
    ]


def ascii_tree(tree: Tree, *, show_status: bool = True, indent: str = "    ") -> str:
    """Indented text, one node per line, e.g. ``    GoToPose "go_to_station" [RUNNING]``."""
    lines = []
    for node, depth in _walk(tree.root):
        status = f" [{node.status.value}]" if show_status else ""
        lines.append(f"{indent * depth}{_label(node)}{status}")
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def dot_tree(tree: Tree, *, show_status: bool = True) -> str:
    """Graphviz dot source: shapes by kind, fill colour by status when ``show_status``."""
    lines = [f"digraph {_quote(tree.tree_id)} {{", "  graph [rankdir=TB];",
             '  node [fontname="Helvetica", style=filled];']
    for node, _depth in _walk(tree.root):
        colour = _STATUS_COLOURS[node.status] if show_status else "white"
        lines.append(f"  n{node.uid} [label={_quote(_label(node))}, shape={_KIND_SHAPES[node.kind]}, "
                     f"fillcolor={colour}];")
    for node, _depth in _walk(tree.root):
        lines.extend(f"  n{node.uid} -> n{child.uid};" for child in node.children_nodes())
    lines.append("}")
    return "\n".join(lines) + "\n"
