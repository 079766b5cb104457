"""Nav2 control nodes, conditions and selectors, and Nav2 Jazzy's default trees run with fake
action leaves through nominal, replanning and recovery scenarios."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.bt import BehaviorTreeFactory, Blackboard, NodeStatus, Tree
from tests.helpers.bt_fakes import F, FakeNav2, R, S, Script, make_factory, register_nav2_fakes

TREES = Path(__file__).resolve().parents[3] / "config" / "trees"
TO_POSE = TREES / "navigate_to_pose_w_replanning_and_recovery.xml"
THROUGH_POSES = TREES / "navigate_through_poses_w_replanning_and_recovery.xml"
DT = 0.125  # s; exact in binary so RateController periods are hit on exact ticks


def build(body: str, script: Script, **kwargs: object) -> Tree:
    xml = f'<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>'
    return make_factory(script).create_tree_from_text(xml, **kwargs)  # type: ignore[arg-type]


def leaves(*names: str) -> str:
    return "".join(f'<Scripted name="{name}"/>' for name in names)


# ---------------------------------------------------------------------- control nodes
def test_pipeline_sequence_reticks_earlier_children_while_a_later_one_runs() -> None:
    script = Script({"a": [S], "b": [R, S], "c": [R, R, S]})
    tree = build(f"<PipelineSequence>{leaves('a', 'b', 'c')}</PipelineSequence>", script)
    assert [tree.tick_once(float(t)) for t in range(4)] == [R, R, R, S]
    assert script.ticks == {"a": 4, "b": 4, "c": 3}


def test_pipeline_sequence_fails_on_any_failure_and_halts_the_rest() -> None:
    script = Script({"a": [S, F], "b": [R]})
    tree = build(f"<PipelineSequence>{leaves('a', 'b')}</PipelineSequence>", script)
    assert [tree.tick_once(0.0), tree.tick_once(1.0)] == [R, F]
    assert script.halts["b"] == 1


def test_recovery_node_retries_action_after_successful_recovery_in_the_same_tick() -> None:
    script = Script({"act": [F, S], "fix": [S]})
    tree = build(f'<RecoveryNode number_of_retries="2">{leaves("act", "fix")}</RecoveryNode>', script)
    assert tree.tick_once(0.0) is S
    assert script.events == ["tick:act", "tick:fix", "tick:act"]


def test_recovery_node_gives_up_after_number_of_retries_or_failed_recovery() -> None:
    script = Script({"act": [F], "fix": [R, S]})
    tree = build(f'<RecoveryNode number_of_retries="1">{leaves("act", "fix")}</RecoveryNode>', script)
    assert [tree.tick_once(0.0), tree.tick_once(1.0)] == [R, F]
    assert script.ticks == {"act": 2, "fix": 2}

    script = Script({"act": [F], "fix": [F]})
    tree = build(f'<RecoveryNode number_of_retries="5">{leaves("act", "fix")}</RecoveryNode>', script)
    assert tree.tick_once(0.0) is F
    assert script.ticks == {"act": 1, "fix": 1}


def test_round_robin_keeps_its_index_across_ticks_and_wraps() -> None:
    script = Script({"a": [S], "b": [S], "c": [S]})
    tree = build(f"<RoundRobin>{leaves('a', 'b', 'c')}</RoundRobin>", script)
    for _ in range(4):
        assert tree.tick_once(0.0) is S
    assert script.events == ["tick:a", "tick:b", "tick:c", "tick:a"]


def test_round_robin_moves_past_failures_and_fails_when_all_fail() -> None:
    script = Script({"a": [F], "b": [R, S], "c": [F]})
    tree = build(f"<RoundRobin>{leaves('a', 'b', 'c')}</RoundRobin>", script)
    assert [tree.tick_once(0.0), tree.tick_once(1.0)] == [R, S]
    assert script.events == ["tick:a", "tick:b", "tick:b"]

    script = Script({"a": [F], "b": [F]})
    tree = build(f"<RoundRobin>{leaves('a', 'b')}</RoundRobin>", script)
    assert tree.tick_once(0.0) is F
    assert tree.root.current_child_idx == 0  # type: ignore[attr-defined]


def test_rate_controller_throttles_but_follows_a_running_child() -> None:
    script = Script({"a": [S, R, R, S, S], "busy": [R]})
    tree = build('<PipelineSequence><RateController hz="2.0"><Scripted name="a"/></RateController>'
                 '<Scripted name="busy"/></PipelineSequence>', script)
    ticked_at = []
    for t in [0.0, 0.25, 0.5, 0.625, 0.75, 1.0, 1.25, 1.5]:
        before = script.ticks["a"]
        tree.tick_once(t)
        if script.ticks["a"] > before:
            ticked_at.append(t)
    # first tick; then once per 0.5 s period, but on every tick while the child is RUNNING;
    # the next period counts from the child's last SUCCESS (0.75 s).
    assert ticked_at == [0.0, 0.5, 0.625, 0.75, 1.25]


def test_goal_updated_fires_once_per_change_after_being_idle() -> None:
    board = Blackboard()
    board.set("goal", (1.0, 2.0))
    tree = build("<GoalUpdated/>", Script(), blackboard=board)
    node = tree.root
    assert node.execute_tick() is F  # first tick from IDLE records the goal
    assert node.execute_tick() is F
    board.set("goal", (3.0, 4.0))
    assert node.execute_tick() is S
    assert node.execute_tick() is F


@pytest.mark.parametrize(("node", "code", "expected"), [
    ("WouldAPlannerRecoveryHelp", 208, S), ("WouldAPlannerRecoveryHelp", 207, S),
    ("WouldAPlannerRecoveryHelp", 200, S), ("WouldAPlannerRecoveryHelp", 204, F),
    ("WouldAPlannerRecoveryHelp", 0, F), ("WouldAControllerRecoveryHelp", 105, S),
    ("WouldAControllerRecoveryHelp", 104, S), ("WouldAControllerRecoveryHelp", 103, F),
])
def test_would_a_recovery_help_error_code_sets(node: str, code: int, expected: NodeStatus) -> None:
    board = Blackboard()
    board.set("code", code)
    assert build(f'<{node} error_code="{{code}}"/>', Script(), blackboard=board).tick_once(0.0) is expected


def test_error_code_conditions_fail_when_the_code_was_never_set() -> None:
    assert build('<WouldAPlannerRecoveryHelp error_code="{none}"/>', Script()).tick_once(0.0) is F
    tree = build('<AreErrorCodesPresent error_code="7" error_codes_to_check="5;7"/>', Script())
    assert tree.tick_once(0.0) is S


def test_selector_uses_default_then_latched_selection() -> None:
    selections: dict[str, str] = {}
    tree = build('<PlannerSelector selected_planner="{p}" default_planner="GridBased"/>', Script(),
                 selection_source=selections.get)
    assert tree.tick_once(0.0) is S and tree.blackboard.get("p") == "GridBased"
    selections["planner_selector"] = "SmacHybrid"
    tree.tick_once(1.0)
    assert tree.blackboard.get("p") == "SmacHybrid"
    del selections["planner_selector"]
    tree.tick_once(2.0)
    assert tree.blackboard.get("p") == "SmacHybrid"  # a received selection sticks


def test_selector_reads_root_blackboard_topic_and_fails_without_any_selection() -> None:
    board = Blackboard()
    body = '<ControllerSelector selected_controller="{c}" topic_name="ctl"/>'
    tree = build(body, Script(), blackboard=board)
    assert tree.tick_once(0.0) is F
    board.set("ctl", "RPP")
    assert tree.tick_once(1.0) is S and board.get("c") == "RPP"


# ---------------------------------------------------------------------- Jazzy default trees
def load_nav_tree(path: Path, fake: FakeNav2, **kwargs: object) -> Tree:
    factory = BehaviorTreeFactory()
    register_nav2_fakes(factory, fake)
    tree = factory.create_tree_from_file(path, **kwargs)  # type: ignore[arg-type]
    tree.blackboard.set("goal", (1.0, 2.0, 0.0))
    tree.blackboard.set("goals", [(1.0, 2.0, 0.0), (2.0, 2.0, 0.0)])
    return tree


def run_to_completion(tree: Tree, max_ticks: int = 5000) -> NodeStatus:
    for k in range(max_ticks):
        status = tree.tick_once(k * DT)
        if status.is_completed:
            return status
    raise AssertionError(f"tree still RUNNING after {max_ticks} ticks")


def test_default_tree_nominal_run_plans_then_follows() -> None:
    fake = FakeNav2()
    assert run_to_completion(load_nav_tree(TO_POSE, fake)) is S
    assert fake.log == ["ComputePathToPose", "FollowPath"]
    planner_inputs = fake.inputs[0][1]
    assert planner_inputs["planner_id"] == "GridBased"
    assert planner_inputs["goal"] == (1.0, 2.0, 0.0)
    assert fake.inputs[1][1]["controller_id"] == "FollowPath"
    assert fake.inputs[1][1]["path"] == "path#1"


def test_default_tree_planner_failure_clears_global_costmap_and_retries() -> None:
    fake = FakeNav2()
    fake.script("ComputePathToPose", 208)  # NO_VALID_PATH once
    assert run_to_completion(load_nav_tree(TO_POSE, fake)) is S
    assert fake.log == ["ComputePathToPose!208", "ClearGlobalCostmap-Context", "ComputePathToPose",
                        "FollowPath"]


def test_default_tree_planner_error_no_recovery_can_fix_fails_at_once() -> None:
    fake = FakeNav2()
    fake.script("ComputePathToPose", 204)  # GOAL_OUTSIDE_MAP: no recovery helps
    assert run_to_completion(load_nav_tree(TO_POSE, fake)) is F
    assert fake.log == ["ComputePathToPose!204"]


def test_default_tree_controller_failures_walk_the_round_robin_recoveries() -> None:
    fake = FakeNav2()
    fake.script("FollowPath", *[105] * 100)  # FAILED_TO_MAKE_PROGRESS forever
    assert run_to_completion(load_nav_tree(TO_POSE, fake)) is F
    contextual = ["ComputePathToPose", "FollowPath!105", "ClearLocalCostmap-Context", "FollowPath!105"]
    system = [entry for entry in fake.log if entry not in contextual]
    assert system == ["ClearLocalCostmap-Subtree", "ClearGlobalCostmap-Subtree", "Spin", "Wait", "BackUp",
                      "ClearLocalCostmap-Subtree", "ClearGlobalCostmap-Subtree", "Spin"]
    assert fake.log[:5] == [*contextual, "ClearLocalCostmap-Subtree"]
    assert fake.log.count("ComputePathToPose") == 7  # first try + 6 retries of the whole task


def test_default_tree_replans_at_1_hz_while_following() -> None:
    fake = FakeNav2(durations={"ComputePathToPose": 1, "FollowPath": 28})
    assert run_to_completion(load_nav_tree(TO_POSE, fake)) is S
    # plan done at t=0.125; follow runs 0.125..3.625; replans start each 1 s after the last plan finished
    assert fake.log == ["ComputePathToPose"] * 4 + ["FollowPath"]
    assert [inputs["path"] for name, inputs in fake.inputs if name == "FollowPath"] == ["path#1"]


def test_halting_the_default_tree_cancels_the_running_action() -> None:
    fake = FakeNav2(durations={"FollowPath": 100})
    tree = load_nav_tree(TO_POSE, fake)
    for k in range(10):
        tree.tick_once(k * DT)
    tree.halt()
    assert fake.log == ["ComputePathToPose", "halted:FollowPath"]
    assert all(node.status is NodeStatus.IDLE for node in tree.nodes)


def test_injected_selection_reaches_the_action_ports() -> None:
    fake = FakeNav2()
    selections = {"controller_selector": "DWB", "planner_selector": "Smac2D"}
    assert run_to_completion(load_nav_tree(TO_POSE, fake, selection_source=selections.get)) is S
    assert fake.inputs[0][1]["planner_id"] == "Smac2D"
    assert fake.inputs[1][1]["controller_id"] == "DWB"


def test_through_poses_tree_runs_and_recovers_from_a_planner_failure() -> None:
    fake = FakeNav2()
    fake.script("ComputePathThroughPoses", 308)
    assert run_to_completion(load_nav_tree(THROUGH_POSES, fake)) is S
    assert fake.log == ["ComputePathThroughPoses!308", "ClearGlobalCostmap-Context",
                        "ComputePathThroughPoses", "FollowPath"]
    assert fake.inputs[0][1]["goals"] == [(1.0, 2.0, 0.0), (2.0, 2.0, 0.0)]


def test_goal_updated_cannot_preempt_a_running_sibling_in_a_reactive_fallback() -> None:
    """BT.CPP 4 resets the non-running children of a ReactiveFallback to IDLE on every tick, so
    GoalUpdated re-reads the goal each time and never fires there (navigation2 issue #6082)."""
    board = Blackboard()
    board.set("goal", (1.0, 2.0))
    script = Script({"recovery": [R]})
    tree = build('<ReactiveFallback><GoalUpdated/><Scripted name="recovery"/></ReactiveFallback>', script,
                 blackboard=board)
    assert tree.tick_once(0.0) is R
    board.set("goal", (5.0, 5.0))
    assert tree.tick_once(1.0) is R
    assert script.halts["recovery"] == 0
