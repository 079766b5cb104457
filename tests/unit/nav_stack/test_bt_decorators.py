"""BT.CPP 4 decorators and leaves: Inverter, Force*, Retry, Repeat, KeepRunningUntilFailure,
Timeout and Delay on the injected clock, non-blocking Sleep, SetBlackboard."""

from __future__ import annotations

import pytest

from nav_stack.core.bt import NodeStatus, Tree
from tests.helpers.bt_fakes import F, R, S, Script, make_factory


def build(body: str, script: Script) -> Tree:
    xml = f'<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>'
    return make_factory(script).create_tree_from_text(xml)


def test_inverter_swaps_success_and_failure_and_passes_running() -> None:
    script = Script({"a": [R, S, F]})
    tree = build('<Inverter><Scripted name="a"/></Inverter>', script)
    assert [tree.tick_once(t) for t in (0.0, 1.0, 2.0)] == [R, F, S]


def test_force_success_and_force_failure() -> None:
    tree = build('<ForceSuccess><Scripted name="a"/></ForceSuccess>', Script({"a": [F]}))
    assert tree.tick_once(0.0) is S
    tree = build('<ForceFailure><Scripted name="a"/></ForceFailure>', Script({"a": [R, S]}))
    assert [tree.tick_once(0.0), tree.tick_once(1.0)] == [R, F]


def test_retry_until_successful_retries_within_one_tick_up_to_num_attempts() -> None:
    script = Script({"a": [F, F, S]})
    tree = build('<RetryUntilSuccessful num_attempts="3"><Scripted name="a"/></RetryUntilSuccessful>', script)
    assert tree.tick_once(0.0) is S
    assert script.ticks["a"] == 3

    script = Script({"a": [F]})
    tree = build('<RetryUntilSuccessful num_attempts="2"><Scripted name="a"/></RetryUntilSuccessful>', script)
    assert tree.tick_once(0.0) is F
    assert script.ticks["a"] == 2


def test_retry_keeps_attempt_count_across_running_ticks() -> None:
    script = Script({"a": [F, R, F, S]})
    tree = build('<RetryUntilSuccessful num_attempts="2"><Scripted name="a"/></RetryUntilSuccessful>', script)
    assert [tree.tick_once(0.0), tree.tick_once(1.0)] == [R, F]


def test_repeat_runs_num_cycles_and_stops_on_failure() -> None:
    script = Script({"a": [S]})
    tree = build('<Repeat num_cycles="4"><Scripted name="a"/></Repeat>', script)
    assert tree.tick_once(0.0) is S
    assert script.ticks["a"] == 4

    script = Script({"a": [S, F]})
    tree = build('<Repeat num_cycles="-1"><Scripted name="a"/></Repeat>', script)
    assert tree.tick_once(0.0) is F
    assert script.ticks["a"] == 2


def test_keep_running_until_failure() -> None:
    script = Script({"a": [S, S, F]})
    tree = build('<KeepRunningUntilFailure><Scripted name="a"/></KeepRunningUntilFailure>', script)
    assert [tree.tick_once(float(t)) for t in range(3)] == [R, R, F]


def test_timeout_halts_a_child_still_running_after_msec_of_tree_time() -> None:
    script = Script({"a": [R]})
    tree = build('<Timeout msec="500"><Scripted name="a"/></Timeout>', script)
    assert [tree.tick_once(t) for t in (10.0, 10.2, 10.49)] == [R, R, R]
    assert tree.tick_once(10.5) is F
    assert script.halts["a"] == 1
    assert script.ticks["a"] == 3  # not ticked on the tick that found the deadline passed


def test_timeout_passes_a_result_that_arrives_in_time_and_rearms() -> None:
    script = Script({"a": [R, S, R]})
    tree = build('<Timeout msec="500"><Scripted name="a"/></Timeout>', script)
    assert [tree.tick_once(0.0), tree.tick_once(0.4)] == [R, S]
    assert [tree.tick_once(0.8), tree.tick_once(1.2)] == [R, R]  # new 0.5 s window from 0.8 s
    assert tree.tick_once(1.3) is F


def test_delay_waits_before_the_first_tick_of_its_child() -> None:
    script = Script({"a": [S]})
    tree = build('<Delay delay_msec="1500"><Scripted name="a"/></Delay>', script)
    assert [tree.tick_once(t) for t in (0.0, 1.0, 1.49)] == [R, R, R]
    assert script.ticks["a"] == 0
    assert tree.tick_once(1.5) is S
    assert tree.tick_once(1.6) is R  # the next run waits again


def test_sleep_is_non_blocking_and_follows_tree_time() -> None:
    tree = build('<Sequence><Sleep msec="2000"/><Scripted name="after"/></Sequence>', Script())
    assert [tree.tick_once(t) for t in (100.0, 101.0, 101.99)] == [R, R, R]
    assert tree.tick_once(102.0) is S


def test_halting_sleep_resets_it() -> None:
    tree = build('<Sleep msec="1000"/>', Script())
    assert tree.tick_once(0.0) is R
    tree.halt()
    assert tree.root.status is NodeStatus.IDLE
    assert tree.tick_once(5.0) is R  # restarted: a fresh 1 s from t = 5


def test_set_blackboard_writes_literal_and_copies_entries() -> None:
    tree = build('<Sequence><SetBlackboard value="42" output_key="answer"/>'
                 '<SetBlackboard value="{answer}" output_key="copy"/></Sequence>', Script())
    assert tree.tick_once(0.0) is S
    assert tree.blackboard.get("answer") == "42"
    assert tree.blackboard.get("copy") == "42"


def test_tree_reads_its_injected_clock_when_now_is_omitted() -> None:
    clock = [10.0]
    xml = '<root BTCPP_format="4"><BehaviorTree><Sleep msec="500"/></BehaviorTree></root>'
    tree = make_factory().create_tree_from_text(xml, clock=lambda: clock[0])
    assert tree.tick_once() is R
    clock[0] = 10.5
    assert tree.tick_once() is S and tree.now == 10.5
    no_clock = make_factory().create_tree_from_text(xml)
    with pytest.raises(ValueError, match="has no clock"):
        no_clock.tick_once()
