"""Blackboard ports: literal conversion by declared type, {key} pointers, outputs, {@key},
SubTree remapping (explicit, literal, _autoremap) and blackboard scoping."""

from __future__ import annotations

from typing import ClassVar

import pytest

from nav_stack.core.bt import (
    BehaviorTreeFactory,
    Blackboard,
    BtPortError,
    NodeConfig,
    NodeStatus,
    PortList,
    SyncActionNode,
    Tree,
    bidirectional_port,
    input_port,
    output_port,
    semicolon_list,
)


class Echo(SyncActionNode):
    """Reads typed inputs, records them, writes ``out`` and increments the inout ``counter``."""

    seen: ClassVar[list[dict[str, object]]] = []

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("count", int, 1),
            input_port("ratio", float, 0.5),
            input_port("flag", bool, False),
            input_port("text", str, "default"),
            input_port("codes", tuple, (), converter=semicolon_list(int)),
            output_port("out", str),
            bidirectional_port("counter", int, "{=}"),
        )

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)

    def tick(self) -> NodeStatus:
        values = {port: self.get_input(port) for port in ("count", "ratio", "flag", "text", "codes")}
        Echo.seen.append(values)
        self.set_output("out", f"{self.name}:{values['text']}")
        self.set_output("counter", int(self.get_input_or("counter", 0)) + 1)
        return NodeStatus.SUCCESS


@pytest.fixture
def factory() -> BehaviorTreeFactory:
    Echo.seen = []
    factory = BehaviorTreeFactory()
    factory.register("Echo", Echo)
    return factory


def load(factory: BehaviorTreeFactory, trees: str, blackboard: Blackboard | None = None) -> Tree:
    xml = f'<root BTCPP_format="4" main_tree_to_execute="Main">{trees}</root>'
    return factory.create_tree_from_text(xml, blackboard=blackboard)


def test_literals_are_converted_by_declared_type(factory: BehaviorTreeFactory) -> None:
    tree = load(factory, '<BehaviorTree ID="Main"><Echo count="7" ratio="0.25" flag="true" text="hi"'
                         ' codes="104;105"/></BehaviorTree>')
    tree.tick_once(0.0)
    assert Echo.seen == [{"count": 7, "ratio": 0.25, "flag": True, "text": "hi", "codes": (104, 105)}]


def test_defaults_apply_when_ports_are_omitted(factory: BehaviorTreeFactory) -> None:
    tree = load(factory, '<BehaviorTree ID="Main"><Echo/></BehaviorTree>')
    tree.tick_once(0.0)
    assert Echo.seen == [{"count": 1, "ratio": 0.5, "flag": False, "text": "default", "codes": ()}]


def test_pointer_reads_blackboard_and_converts_stored_strings(factory: BehaviorTreeFactory) -> None:
    board = Blackboard()
    board.set("n", "12")  # strings on the blackboard convert to the port type, as in BT.CPP
    board.set("r", 2.5)
    tree = load(factory, '<BehaviorTree ID="Main"><Echo count="{n}" ratio="{r}" out="{result}"/>'
                         '</BehaviorTree>', board)
    tree.tick_once(0.0)
    assert Echo.seen[0]["count"] == 12
    assert Echo.seen[0]["ratio"] == 2.5
    assert board.get("result") == "Echo:default"
    assert board.get("counter") == 1  # the {=} default wires the inout port to its own name


def test_missing_blackboard_entry_raises_naming_node_and_port(factory: BehaviorTreeFactory) -> None:
    tree = load(factory, '<BehaviorTree ID="Main"><Echo name="e" count="{nowhere}"/></BehaviorTree>')
    with pytest.raises(BtPortError, match=r"e::1.*'count'.*nowhere"):
        tree.tick_once(0.0)


def test_unconvertible_blackboard_string_raises(factory: BehaviorTreeFactory) -> None:
    board = Blackboard()
    board.set("n", "many")
    tree = load(factory, '<BehaviorTree ID="Main"><Echo count="{n}"/></BehaviorTree>', board)
    with pytest.raises(BtPortError, match="'many' is not a valid int"):
        tree.tick_once(0.0)


def test_subtree_explicit_remapping_and_literals(factory: BehaviorTreeFactory) -> None:
    trees = ('<BehaviorTree ID="Main"><Sequence>'
             '<SubTree ID="Sub" text="literal" result="{parent_result}"/>'
             '<Echo name="reader" text="{parent_result}"/></Sequence></BehaviorTree>'
             '<BehaviorTree ID="Sub"><Echo name="inner" text="{text}" out="{result}"/></BehaviorTree>')
    tree = load(factory, trees)
    assert tree.tick_once(0.0) is NodeStatus.SUCCESS
    assert tree.blackboard.get("parent_result") == "inner:literal"
    assert Echo.seen[1]["text"] == "inner:literal"
    assert "result" not in tree.blackboard  # the internal name stays inside the subtree


def test_subtree_without_remapping_is_isolated(factory: BehaviorTreeFactory) -> None:
    board = Blackboard()
    board.set("text", "outer")
    trees = ('<BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree>'
             '<BehaviorTree ID="Sub"><Echo text="{text}" out="{local}"/></BehaviorTree>')
    tree = load(factory, trees, board)
    with pytest.raises(BtPortError, match="text"):
        tree.tick_once(0.0)


def test_subtree_autoremap_shares_parent_keys_but_not_private_ones(factory: BehaviorTreeFactory) -> None:
    board = Blackboard()
    board.set("text", "outer")
    trees = ('<BehaviorTree ID="Main"><SubTree ID="Sub" _autoremap="true"/></BehaviorTree>'
             '<BehaviorTree ID="Sub"><Sequence><Echo text="{text}" out="{shared}"/>'
             '<Echo text="x" out="{_private}"/></Sequence></BehaviorTree>')
    tree = load(factory, trees, board)
    tree.tick_once(0.0)
    assert board.get("shared") == "Echo:outer"
    assert "_private" not in board


def test_at_key_addresses_the_root_blackboard_from_a_subtree(factory: BehaviorTreeFactory) -> None:
    board = Blackboard()
    board.set("text", "from-root")
    trees = ('<BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree>'
             '<BehaviorTree ID="Sub"><Echo text="{@text}" out="{@written}"/></BehaviorTree>')
    load(factory, trees, board).tick_once(0.0)
    assert board.get("written") == "Echo:from-root"


def test_nested_subtrees_chain_remapping(factory: BehaviorTreeFactory) -> None:
    trees = ('<BehaviorTree ID="Main"><SubTree ID="A" a_out="{top}"/></BehaviorTree>'
             '<BehaviorTree ID="A"><SubTree ID="B" b_out="{a_out}"/></BehaviorTree>'
             '<BehaviorTree ID="B"><Echo text="deep" out="{b_out}"/></BehaviorTree>')
    tree = load(factory, trees)
    tree.tick_once(0.0)
    assert tree.blackboard.get("top") == "Echo:deep"


def test_set_output_returns_false_when_not_wired(factory: BehaviorTreeFactory) -> None:
    tree = load(factory, '<BehaviorTree ID="Main"><Echo/></BehaviorTree>')
    node = tree.root
    assert isinstance(node, Echo)
    assert node.set_output("out", "x") is False
    with pytest.raises(BtPortError, match="not an output port"):
        node.set_output("count", 3)
