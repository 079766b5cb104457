"""Loading BT.CPP XML: v3 and v4 forms, includes, and load errors that name file, line and node."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.bt import BehaviorTreeFactory, BtLoadError, NodeKind, NodeStatus, SyncActionNode
from nav_stack.core.bt.controls import SequenceWithMemory
from tests.helpers.bt_fakes import Script, Scripted, make_factory
from tests.helpers.bt_seed_fakes import SeedWorld, register_seed_fakes

TREES = Path(__file__).resolve().parents[3] / "config" / "trees"


def write(tmp_path: Path, text: str, name: str = "tree.xml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def load_error(tmp_path: Path, text: str, factory: BehaviorTreeFactory | None = None) -> BtLoadError:
    path = write(tmp_path, text)
    with pytest.raises(BtLoadError) as info:
        (factory or make_factory()).create_tree_from_file(path)
    assert str(path) in str(info.value)
    return info.value


def test_v3_root_without_format_and_sequence_star_alias() -> None:
    xml = ('<root main_tree_to_execute="MainTree">\n  <BehaviorTree ID="MainTree">\n'
           '    <SequenceStar><AlwaysSuccess/></SequenceStar>\n  </BehaviorTree>\n</root>')
    tree = make_factory().create_tree_from_text(xml)
    assert isinstance(tree.root, SequenceWithMemory)
    assert tree.tick_once(0.0) is NodeStatus.SUCCESS


def test_sequence_star_is_not_a_v4_name() -> None:
    xml = ('<root BTCPP_format="4"><BehaviorTree ID="T">'
           '<SequenceStar><AlwaysSuccess/></SequenceStar></BehaviorTree></root>')
    with pytest.raises(BtLoadError, match="unknown node type 'SequenceStar'"):
        make_factory().create_tree_from_text(xml)


def test_seed_v3_and_v4_files_load_to_the_same_structure() -> None:
    shapes = []
    for name in ("seed_battery_patrol_v3.xml", "seed_battery_patrol_v4.xml"):
        factory = BehaviorTreeFactory()
        register_seed_fakes(factory, SeedWorld())
        tree = factory.create_tree_from_file(TREES / name)
        shapes.append([(node.registration_id, node.config.ports, node.parent.uid if node.parent else 0)
                       for node in tree.nodes])
    assert shapes[0] == shapes[1]
    assert len(shapes[0]) == 19
    assert [row[0] for row in shapes[0][:3]] == ["Fallback", "Sequence", "IsBatteryLow"]


def test_explicit_action_form_and_multiple_trees_with_main_tree_id() -> None:
    xml = ('<root BTCPP_format="4"><BehaviorTree ID="A"><Action ID="Scripted" name="x"/></BehaviorTree>'
           '<BehaviorTree ID="B"><AlwaysFailure/></BehaviorTree></root>')
    factory = make_factory()
    assert factory.create_tree_from_text(xml, main_tree_id="A").root.name == "x"
    with pytest.raises(BtLoadError, match="several trees"):
        factory.create_tree_from_text(xml)


def test_include_loads_trees_from_another_file(tmp_path: Path) -> None:
    write(tmp_path, '<root BTCPP_format="4"><BehaviorTree ID="Sub"><AlwaysSuccess/></BehaviorTree></root>',
          "sub.xml")
    main = write(tmp_path, '<root BTCPP_format="4" main_tree_to_execute="Main"><include path="sub.xml"/>'
                           '<BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree></root>')
    tree = make_factory().create_tree_from_file(main)
    assert tree.root.kind is NodeKind.SUBTREE
    assert tree.tick_once(0.0) is NodeStatus.SUCCESS


def test_malformed_xml_names_file_and_line(tmp_path: Path) -> None:
    error = load_error(tmp_path, '<root BTCPP_format="4">\n<BehaviorTree ID="T">\n<Sequence>\n'
                                 '</BehaviorTree>\n</root>')
    assert error.line == 4
    assert "malformed XML" in str(error)


def test_unknown_node_names_file_line_and_node(tmp_path: Path) -> None:
    error = load_error(tmp_path, '<root BTCPP_format="4">\n<BehaviorTree ID="T">\n<Sequence>\n'
                                 '  <Teleport name="beam_me_up"/>\n</Sequence></BehaviorTree></root>')
    assert error.line == 4
    assert 'name="beam_me_up"' in str(error)
    assert "unknown node type 'Teleport'" in str(error)


def test_missing_required_port(tmp_path: Path) -> None:
    factory = BehaviorTreeFactory()
    register_seed_fakes(factory, SeedWorld())
    xml = '<root>\n<BehaviorTree ID="T">\n  <GoToPose name="go"/>\n</BehaviorTree></root>'
    error = load_error(tmp_path, xml, factory)
    assert (error.line, error.node) == (3, '<GoToPose name="go">')
    assert "missing required port 'loc'" in str(error)


def test_bad_port_value_is_rejected_at_load(tmp_path: Path) -> None:
    error = load_error(tmp_path, '<root BTCPP_format="4"><BehaviorTree>\n<RateController hz="fast">'
                                 '<AlwaysSuccess/></RateController></BehaviorTree></root>')
    assert error.line == 2
    assert "port 'hz'" in str(error) and "'fast'" in str(error)


def test_unknown_port_attribute_lists_known_ports(tmp_path: Path) -> None:
    error = load_error(tmp_path, '<root BTCPP_format="4"><BehaviorTree>\n\n<Timeout msecs="5">'
                                 '<AlwaysSuccess/></Timeout></BehaviorTree></root>')
    assert error.line == 3
    assert "'msecs' is not a port of Timeout (ports: msec)" in str(error)


def test_unknown_and_recursive_subtree_ids(tmp_path: Path) -> None:
    error = load_error(tmp_path, '<root BTCPP_format="4" main_tree_to_execute="T">'
                                 '<BehaviorTree ID="T">\n<SubTree ID="Nope"/></BehaviorTree></root>')
    assert error.line == 2 and "unknown SubTree ID 'Nope'" in str(error)
    error = load_error(tmp_path, '<root BTCPP_format="4" main_tree_to_execute="T">'
                                 '<BehaviorTree ID="T"><SubTree ID="U"/></BehaviorTree>'
                                 '<BehaviorTree ID="U"><SubTree ID="T"/></BehaviorTree></root>')
    assert "includes itself (T -> U)" in str(error)


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("<Inverter/>", "a decorator needs exactly one child, found 0"),
        ("<Sequence/>", "needs at least 1 children, found 0"),
        ("<RecoveryNode><AlwaysSuccess/></RecoveryNode>", "needs exactly 2 children, found 1"),
        ("<AlwaysSuccess><AlwaysSuccess/></AlwaysSuccess>", "a leaf node cannot have children"),
        ('<AlwaysSuccess _skipIf="x"/>', "script attribute '_skipIf' is not supported"),
    ],
)
def test_structure_errors(tmp_path: Path, body: str, message: str) -> None:
    error = load_error(tmp_path, f'<root BTCPP_format="4"><BehaviorTree>{body}</BehaviorTree></root>')
    assert message in str(error)


def test_root_and_format_errors(tmp_path: Path) -> None:
    assert "must be <root>" in str(load_error(tmp_path, "<tree/>"))
    assert "BTCPP_format '5'" in str(load_error(tmp_path, '<root BTCPP_format="5"/>'))
    xml = '<root main_tree_to_execute="X"><BehaviorTree ID="T"><AlwaysSuccess/></BehaviorTree></root>'
    assert "main tree 'X' not found" in str(load_error(tmp_path, xml))


def test_missing_file_is_a_load_error(tmp_path: Path) -> None:
    with pytest.raises(BtLoadError, match="cannot read file"):
        make_factory().create_tree_from_file(tmp_path / "absent.xml")


def test_registration_errors() -> None:
    factory = make_factory()
    with pytest.raises(ValueError, match="already registered"):
        factory.register("Scripted", Scripted, script=Script())
    with pytest.raises(ValueError, match="reserved"):
        factory.register("SubTree", SyncActionNode)
    with pytest.raises(ValueError, match="not a TreeNode subclass"):
        factory.register("Thing", dict)  # type: ignore[arg-type]


def test_constructor_failure_is_reported_with_location(tmp_path: Path) -> None:
    factory = BehaviorTreeFactory()
    factory.register("Scripted", Scripted)  # the required ``script`` argument is missing
    error = load_error(tmp_path, '<root BTCPP_format="4"><BehaviorTree>\n<Scripted name="s"/>'
                                 '</BehaviorTree></root>', factory)
    assert error.line == 2 and "creating Scripted failed" in str(error)
