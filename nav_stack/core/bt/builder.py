"""Turns parsed BT.CPP XML (v4, and the v3 form) into node objects, checking everything it can.

Every error raised here is a ``BtLoadError`` naming file, line and element: unknown node types,
wrong child counts, unknown or missing ports, literals that do not convert to the port type,
unknown or recursive SubTree IDs, bad ``<root>`` structure and unreadable includes.

v3 compatibility (the seed's tree.xml): a ``<root>`` without ``BTCPP_format`` (or with "3") is read
as v3, where ``SequenceStar`` means SequenceWithMemory, ``SubTreePlus`` means SubTree and
``__shared_blackboard``/``__autoremap`` mean ``_autoremap``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from nav_stack.core.bt.blackboard import Blackboard
from nav_stack.core.bt.decorators import SubTreeNode
from nav_stack.core.bt.errors import BtError
from nav_stack.core.bt.node import ControlNode, DecoratorNode, NodeConfig, TreeContext, TreeNode
from nav_stack.core.bt.ports import PortDirection, PortInfo, blackboard_key, to_bool
from nav_stack.core.bt.status import NodeKind
from nav_stack.core.bt.tree import Tree
from nav_stack.core.bt.xml_model import XmlElement, parse_xml_file

if TYPE_CHECKING:
    from nav_stack.core.bt.factory import NodeRegistration

V3_ALIASES = {"SequenceStar": "SequenceWithMemory", "FallbackStar": "Fallback"}
EXPLICIT_TAGS = frozenset({"Action", "Condition", "Control", "Decorator"})
SCRIPT_ATTRIBUTES = frozenset({"_skipIf", "_successIf", "_failureIf", "_while", "_onSuccess", "_onFailure",
                               "_onHalted", "_post"})
IGNORED_ATTRIBUTES = frozenset({"_description", "_uid", "_fullpath"})
SUBTREE_AUTOREMAP = ("_autoremap", "__autoremap", "__shared_blackboard")


@dataclass
class _TreeDef:
    """A ``<BehaviorTree>`` element and the format of the file it came from."""

    element: XmlElement
    v3: bool


class TreeBuilder:
    """Builds one ``Tree`` from a parsed document (single use)."""

    def __init__(self, registry: Mapping[str, NodeRegistration], context: TreeContext) -> None:
        self._registry = registry
        self._context = context
        self._defs: dict[str, _TreeDef] = {}
        self._nodes: list[TreeNode] = []
        self._next_uid = 1
        self._files: set[Path] = set()

    # ------------------------------------------------------------------ documents
    def build(self, root: XmlElement, base_dir: Path, main_tree_id: str | None, blackboard: Blackboard,
              clock: Callable[[], float] | None) -> Tree:
        """Collect the tree definitions of ``root`` (and its includes) and instantiate the main tree."""
        main_attr = self._collect(root, base_dir)
        tree_id = main_tree_id or main_attr
        if tree_id is None:
            if len(self._defs) != 1:
                raise root.error(f"several trees ({', '.join(sorted(self._defs))}): "
                                 "set main_tree_to_execute or pass main_tree_id")
            tree_id = next(iter(self._defs))
        if tree_id not in self._defs:
            raise root.error(f"main tree '{tree_id}' not found (trees: {', '.join(sorted(self._defs))})")
        tree_def = self._defs[tree_id]
        top = self._build_node(tree_def.element.children[0], blackboard, tree_id, tree_def.v3, (tree_id,))
        self._nodes.sort(key=lambda node: node.uid)
        return Tree(top, self._nodes, blackboard, self._context, tree_id, root.source, clock)

    def _collect(self, root: XmlElement, base_dir: Path) -> str | None:
        if root.tag != "root":
            raise root.error("the document element must be <root>")
        fmt = root.attrib.get("BTCPP_format", "3")
        if fmt not in ("3", "4"):
            raise root.error(f"BTCPP_format '{fmt}' is not supported (use 4, or omit it for v3)")
        for child in root.children:
            if child.tag == "BehaviorTree":
                tree_id = child.attrib.get("ID", "MainTree")
                if tree_id in self._defs:
                    raise child.error(f"BehaviorTree ID '{tree_id}' is defined twice")
                if len(child.children) != 1:
                    found = len(child.children)
                    raise child.error(f"a BehaviorTree must have exactly one child, found {found}")
                self._defs[tree_id] = _TreeDef(child, v3=fmt == "3")
            elif child.tag == "include":
                self._include(child, base_dir)
            elif child.tag != "TreeNodesModel":
                raise child.error(f"unexpected element <{child.tag}> under <root>")
        return root.attrib.get("main_tree_to_execute")

    def _include(self, element: XmlElement, base_dir: Path) -> None:
        if "ros_pkg" in element.attrib:
            raise element.error("<include ros_pkg=...> is not supported; use a path")
        if "path" not in element.attrib:
            raise element.error("<include> needs a path attribute")
        path = (base_dir / element.attrib["path"]).resolve()
        if path in self._files:
            raise element.error(f"'{path}' is included twice")
        self._files.add(path)
        try:
            self._collect(parse_xml_file(path), path.parent)
        except BtError as exc:
            raise element.error(f"in included file: {exc}") from exc

    # ------------------------------------------------------------------ nodes
    def _build_node(self, element: XmlElement, board: Blackboard, path: str, v3: bool,
                    subtrees: tuple[str, ...]) -> TreeNode:
        attrs = dict(element.attrib)
        if element.tag == "SubTree" or (v3 and element.tag == "SubTreePlus"):
            return self._build_subtree(element, attrs, board, path, v3, subtrees)
        if element.tag in EXPLICIT_TAGS:
            if "ID" not in attrs:
                raise element.error(f"<{element.tag}> needs an ID attribute")
            type_id = attrs.pop("ID")
        else:
            type_id = element.tag
        if v3:
            type_id = V3_ALIASES.get(type_id, type_id)
        registration = self._registry.get(type_id)
        if registration is None:
            raise element.error(f"unknown node type '{type_id}' (not registered in the factory)")
        name = attrs.pop("name", type_id)
        kind = registration.node_type.kind
        self._check_children(element, registration.node_type, kind)
        ports = self._ports(element, attrs, registration.manifest, type_id)
        config = self._config(board, ports, registration.manifest, type_id, f"{path}/{name}", element)
        try:
            node = registration.create(name, config)
        except BtError:
            raise
        except Exception as exc:  # a node constructor rejected its arguments
            raise element.error(f"creating {type_id} failed: {type(exc).__name__}: {exc}") from exc
        self._nodes.append(node)
        for child_element in element.children:
            child = self._build_node(child_element, board, config.path, v3, subtrees)
            self._attach(node, child)
        return node

    def _config(self, board: Blackboard, ports: dict[str, Any], manifest: Mapping[str, PortInfo],
                type_id: str, path: str, element: XmlElement) -> NodeConfig:
        uid = self._next_uid
        self._next_uid += 1
        return NodeConfig(board, ports, dict(manifest), self._context, type_id, uid, f"{path}::{uid}",
                          f"{element.source}:{element.line}")

    def _attach(self, parent: TreeNode, child: TreeNode) -> None:
        child.parent = parent
        if isinstance(parent, ControlNode):
            parent.children.append(child)
        elif isinstance(parent, DecoratorNode):
            parent.set_child(child)

    @staticmethod
    def _check_children(element: XmlElement, node_type: type[TreeNode], kind: NodeKind) -> None:
        count = len(element.children)
        if kind is NodeKind.CONTROL and issubclass(node_type, ControlNode):
            low, high = node_type.min_children, node_type.max_children
            if count < low or (high is not None and count > high):
                wanted = f"exactly {low}" if high == low else f"at least {low}"
                raise element.error(f"a {element.tag} control node needs {wanted} children, found {count}")
        elif kind is NodeKind.DECORATOR and count != 1:
            raise element.error(f"a decorator needs exactly one child, found {count}")
        elif kind in (NodeKind.ACTION, NodeKind.CONDITION) and count:
            raise element.error(f"a leaf node cannot have children, found {count}")

    @staticmethod
    def _ports(element: XmlElement, attrs: dict[str, str], manifest: Mapping[str, PortInfo],
               type_id: str) -> dict[str, Any]:
        ports: dict[str, Any] = {}
        for attr, value in attrs.items():
            if attr in SCRIPT_ATTRIBUTES:
                raise element.error(f"script attribute '{attr}' is not supported by this engine")
            if attr in IGNORED_ATTRIBUTES:
                continue
            info = manifest.get(attr)
            if info is None:
                known = ", ".join(sorted(manifest)) or "none"
                raise element.error(f"'{attr}' is not a port of {type_id} (ports: {known})")
            if info.direction is PortDirection.INPUT and blackboard_key(value) is None:
                try:
                    info.convert(value)
                except ValueError as exc:
                    raise element.error(f"port '{attr}': {exc}") from None
            ports[attr] = value
        for info in manifest.values():
            if info.name in ports:
                continue
            if info.has_default:
                ports[info.name] = info.default
            elif info.required:
                raise element.error(f"missing required port '{info.name}' of {type_id}")
        return ports

    def _build_subtree(self, element: XmlElement, attrs: dict[str, str], board: Blackboard, path: str,
                       v3: bool, subtrees: tuple[str, ...]) -> TreeNode:
        subtree_id = attrs.pop("ID", None)
        if subtree_id is None:
            raise element.error("<SubTree> needs an ID attribute")
        if subtree_id not in self._defs:
            raise element.error(f"unknown SubTree ID '{subtree_id}' (trees: {', '.join(sorted(self._defs))})")
        if subtree_id in subtrees:
            raise element.error(f"SubTree '{subtree_id}' includes itself ({' -> '.join(subtrees)})")
        if element.children:
            raise element.error("a <SubTree> element cannot have children")
        name = attrs.pop("name", subtree_id)
        config = self._config(board, {}, {}, "SubTree", f"{path}/{name}", element)
        sub_board = Blackboard(parent=board, name=config.path)
        for attr, value in attrs.items():
            if attr in SUBTREE_AUTOREMAP:
                try:
                    sub_board.enable_autoremap(to_bool(value))
                except ValueError as exc:
                    raise element.error(f"{attr}: {exc}") from None
            elif attr in IGNORED_ATTRIBUTES:
                continue
            elif attr.startswith("_"):
                raise element.error(f"attribute '{attr}' is not supported on <SubTree>")
            else:
                key = blackboard_key(value)
                if key is None:
                    sub_board.set(attr, value)
                else:
                    sub_board.add_remapping(attr, attr if key == "=" else key)
        config.blackboard = sub_board
        node = SubTreeNode(name, config, subtree_id)
        self._nodes.append(node)
        tree_def = self._defs[subtree_id]
        child = self._build_node(tree_def.element.children[0], sub_board, config.path, tree_def.v3,
                                 (*subtrees, subtree_id))
        self._attach(node, child)
        return node
