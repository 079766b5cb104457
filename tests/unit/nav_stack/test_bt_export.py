"""Views of a running tree: indented ascii with statuses, Graphviz dot, status snapshot, listeners."""

from __future__ import annotations

from nav_stack.core.bt import NodeStatus, Tree, ascii_tree, dot_tree, snapshot
from tests.helpers.bt_fakes import R, S, Script, make_factory

XML = ('<root BTCPP_format="4" main_tree_to_execute="Main">'
       '<BehaviorTree ID="Main"><Sequence name="top"><Scripted name="done"/>'
       '<Inverter><Scripted name="busy"/></Inverter><SubTree ID="Sub" name="sub"/></Sequence></BehaviorTree>'
       '<BehaviorTree ID="Sub"><AlwaysSuccess name="say &quot;hi&quot;"/></BehaviorTree></root>')


def running_tree() -> Tree:
    tree = make_factory(Script({"done": [S], "busy": [R]})).create_tree_from_text(XML)
    tree.tick_once(0.0)
    return tree


def test_ascii_tree_shows_structure_names_and_live_statuses() -> None:
    assert ascii_tree(running_tree()) == (
        'Sequence "top" [RUNNING]\n'
        '    Scripted "done" [SUCCESS]\n'
        "    Inverter [RUNNING]\n"
        '        Scripted "busy" [RUNNING]\n'
        '    SubTree[Sub] "sub" [IDLE]\n'
        '        AlwaysSuccess "say "hi"" [IDLE]\n'
    )


def test_ascii_tree_without_statuses() -> None:
    assert ascii_tree(running_tree(), show_status=False).splitlines()[2] == "    Inverter"


def test_dot_tree_has_one_node_per_tree_node_and_parent_edges() -> None:
    dot = dot_tree(running_tree())
    assert dot.startswith('digraph "Main" {')
    assert dot.count("[label=") == 6
    assert "n1 -> n2;" in dot and "n3 -> n4;" in dot and "n5 -> n6;" in dot
    assert 'label="AlwaysSuccess \\"say \\"hi\\"\\""' in dot
    assert "n4 [label=\"Scripted \\\"busy\\\"\", shape=ellipse, fillcolor=orange];" in dot


def test_snapshot_lists_uid_parent_type_and_status() -> None:
    rows = snapshot(running_tree())
    assert [(r.uid, r.parent_uid, r.type_id, r.status, r.depth) for r in rows] == [
        (1, 0, "Sequence", "RUNNING", 0),
        (2, 1, "Scripted", "SUCCESS", 1),
        (3, 1, "Inverter", "RUNNING", 1),
        (4, 3, "Scripted", "RUNNING", 2),
        (5, 1, "SubTree", "IDLE", 1),
        (6, 5, "AlwaysSuccess", "IDLE", 2),
    ]
    assert rows[4].kind == "SubTree"
    assert rows[1].as_dict()["name"] == "done"


def test_status_listener_sees_every_transition() -> None:
    tree = make_factory(Script({"done": [S], "busy": [R]})).create_tree_from_text(XML)
    changes: list[tuple[str, NodeStatus, NodeStatus]] = []
    tree.add_status_listener(lambda node, old, new: changes.append((node.name, old, new)))
    tree.tick_once(0.0)
    tree.halt()
    assert ("busy", NodeStatus.IDLE, NodeStatus.RUNNING) in changes
    assert ("busy", NodeStatus.RUNNING, NodeStatus.IDLE) in changes
    assert changes[-1] == ("top", NodeStatus.RUNNING, NodeStatus.IDLE)
