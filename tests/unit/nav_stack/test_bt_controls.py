"""BT.CPP 4 control-node semantics: resume vs. reactive re-tick, memory, halting, Parallel thresholds."""

from __future__ import annotations

import pytest

from nav_stack.core.bt import NodeStatus, Tree
from tests.helpers.bt_fakes import F, K, R, S, Script, make_factory


def build(body: str, script: Script) -> Tree:
    xml = f'<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>'
    return make_factory(script).create_tree_from_text(xml)


def run(tree: Tree, ticks: int) -> list[NodeStatus]:
    return [tree.tick_once(float(k)) for k in range(ticks)]


def leaves(*names: str) -> str:
    return "".join(f'<Scripted name="{name}"/>' for name in names)


def test_sequence_resumes_at_running_child_without_reticking_earlier_ones() -> None:
    script = Script({"a": [S], "b": [R, R, S], "c": [S]})
    tree = build(f"<Sequence>{leaves('a', 'b', 'c')}</Sequence>", script)
    assert run(tree, 3) == [R, R, S]
    assert script.ticks == {"a": 1, "b": 3, "c": 1}


def test_sequence_failure_resets_to_first_child() -> None:
    script = Script({"a": [S], "b": [F, S], "c": [S]})
    tree = build(f"<Sequence>{leaves('a', 'b', 'c')}</Sequence>", script)
    assert run(tree, 2) == [F, S]
    assert script.ticks["a"] == 2  # restarted from the first child after the failure


def test_sequence_with_memory_retries_the_failed_child_only() -> None:
    script = Script({"a": [S], "b": [F, S], "c": [S]})
    tree = build(f"<SequenceWithMemory>{leaves('a', 'b', 'c')}</SequenceWithMemory>", script)
    assert run(tree, 2) == [F, S]
    assert script.ticks == {"a": 1, "b": 2, "c": 1}


def test_fallback_resumes_and_stops_at_first_success() -> None:
    script = Script({"a": [F], "b": [R, S], "c": [S]})
    tree = build(f"<Fallback>{leaves('a', 'b', 'c')}</Fallback>", script)
    assert run(tree, 2) == [R, S]
    assert script.ticks == {"a": 1, "b": 2}


def test_fallback_fails_when_all_children_fail() -> None:
    script = Script({"a": [F], "b": [F]})
    tree = build(f"<Fallback>{leaves('a', 'b')}</Fallback>", script)
    assert run(tree, 1) == [F]


def test_reactive_sequence_reticks_conditions_and_halts_running_child() -> None:
    script = Script({"cond": [S, S, F], "act": [R]})
    tree = build(f"<ReactiveSequence>{leaves('cond', 'act')}</ReactiveSequence>", script)
    assert run(tree, 3) == [R, R, F]
    assert script.ticks == {"cond": 3, "act": 2}
    assert script.halts["act"] == 1
    assert tree.find("act")[0].status is NodeStatus.IDLE


def test_reactive_fallback_halts_running_sibling_when_earlier_child_succeeds() -> None:
    script = Script({"cond": [F, F, S], "act": [R]})
    tree = build(f"<ReactiveFallback>{leaves('cond', 'act')}</ReactiveFallback>", script)
    assert run(tree, 3) == [R, R, S]
    assert script.halts["act"] == 1
    assert script.events[-2:] == ["tick:cond", "halt:act"]


def test_reactive_sequence_resets_earlier_children_to_idle_while_one_runs() -> None:
    script = Script({"cond": [S], "act": [R]})
    tree = build(f"<ReactiveSequence>{leaves('cond', 'act')}</ReactiveSequence>", script)
    run(tree, 1)
    assert tree.find("cond")[0].status is NodeStatus.IDLE
    assert tree.find("act")[0].status is NodeStatus.RUNNING


def test_halting_a_sequence_halts_the_running_descendant_and_resets_all() -> None:
    script = Script({"a": [S], "b": [R]})
    tree = build(f"<Sequence><Inverter><Sequence>{leaves('a', 'b')}</Sequence></Inverter></Sequence>", script)
    run(tree, 2)
    tree.halt()
    assert script.halts["b"] == 1
    assert all(node.status is NodeStatus.IDLE for node in tree.nodes)
    assert run(tree, 1) == [R]
    assert script.ticks["a"] == 2  # restarted from scratch after the halt


def test_parallel_default_thresholds_need_all_successes_and_fail_on_first_failure() -> None:
    script = Script({"a": [S], "b": [R, S], "c": [R, R, S]})
    tree = build(f"<Parallel>{leaves('a', 'b', 'c')}</Parallel>", script)
    assert run(tree, 3) == [R, R, S]
    assert script.ticks == {"a": 1, "b": 2, "c": 3}  # finished children are not ticked again

    script2 = Script({"a": [R], "b": [F]})
    tree2 = build(f"<Parallel>{leaves('a', 'b')}</Parallel>", script2)
    assert run(tree2, 1) == [F]
    assert script2.halts["a"] == 1


def test_parallel_success_count_one_halts_the_others() -> None:
    script = Script({"a": [R], "b": [R, S]})
    tree = build(f'<Parallel success_count="1">{leaves("a", "b")}</Parallel>', script)
    assert run(tree, 2) == [R, S]
    assert script.halts["a"] == 1


def test_parallel_failure_count_two_tolerates_one_failure() -> None:
    script = Script({"a": [F], "b": [R, F], "c": [R]})
    tree = build(f'<Parallel success_count="1" failure_count="2">{leaves("a", "b", "c")}</Parallel>', script)
    assert run(tree, 2) == [R, F]


def test_skipped_children_are_skipped_by_sequence() -> None:
    script = Script({"a": [K], "b": [K]})
    tree = build(f"<Sequence>{leaves('a', 'b')}</Sequence>", script)
    assert run(tree, 1) == [K]
    assert tree.root.status is NodeStatus.IDLE


def test_child_returning_idle_is_an_error_naming_the_parent() -> None:
    script = Script({"a": [NodeStatus.IDLE]})
    tree = build(f"<Sequence name='seq'>{leaves('a')}</Sequence>", script)
    with pytest.raises(RuntimeError, match="a::2"):
        tree.tick_once(0.0)
