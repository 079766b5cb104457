"""Judging a run (verdict), reading a mission's console lines (outcome) and the command lines that run a
scenario (commands). Pure: no process is started."""

from __future__ import annotations

from pathlib import Path

import yaml

from navsuite_tools.scenarios import commands, outcome
from navsuite_tools.scenarios.farm import select
from navsuite_tools.scenarios.schema import Expect, parse_scenarios
from navsuite_tools.scenarios.verdict import Outcome, judge

REPO = Path(__file__).resolve().parents[3]

DEMO_SUCCESS = """\
[demo] [t=0.38 s] StAllSensorsGo -> StSetInitialPose [NAV2_READY] on EvCbSuccess[CbWaitNav2Nodes, OrNav]
[demo] [t=41.45 s] StNavigateToWaypoint2 -> StFinalState [SUCCESS] on EvActionSucceeded[ClNav2Z, OrNavigation]
[demo] ---------------- summary ----------------
[demo] transitions: 5; sim time 43.0 s; wall time 10.6 s; real-time factor 5.7
[demo] result: SUCCESS: mission complete
""".splitlines()
DEMO_ABORT = """\
[demo] [t=14.71 s] StNavigateToWaypoint1 -> StFinalState [ABORT] on EvActionAborted[ClNav2Z, OrNavigation] \
(error_code 208: 'compute_path_to_pose' failed with error code 208 (NO_VALID_PATH))
[demo] transitions: 3; sim time 14.9 s; wall time 11.9 s; real-time factor 2.8
[demo] result: ABORT: StNavigateToWaypoint1 -> StFinalState on EvActionAborted[ClNav2Z, OrNavigation]
""".splitlines()


def _outcome(**fields: object) -> Outcome:
    base: dict[str, object] = {"result": "SUCCESS", "final_state": "StFinalState", "tag": "SUCCESS",
                               "result_code": 0, "sim_time": 40.0, "collisions": 0,
                               "max_localization_error": 0.1}
    return Outcome(**{**base, **fields})  # type: ignore[arg-type]


def test_a_run_meeting_every_criterion_passes() -> None:
    expect = Expect("SUCCESS", "StFinalState", "SUCCESS", 0, 60.0, 0, 0.5)
    verdict = judge(expect, _outcome())
    assert verdict.passed and verdict.failures == () and verdict.criterion == ""


def test_each_failing_criterion_is_named_first_one_first() -> None:
    expect = Expect("SUCCESS", None, None, 0, 30.0, 0, 0.05)
    verdict = judge(expect, _outcome(result="ABORT", detail="no path", result_code=208))
    assert not verdict.passed
    assert verdict.criterion == "result"
    assert verdict.failures == ("result: expected SUCCESS, got ABORT (no path)",
                                "result_code: expected 0, got 208",
                                "max_sim_time: 40 s > 30 s",
                                "max_localization_error: 0.1 m > 0.05 m")


def test_collisions_fail_the_default_zero_collision_criterion() -> None:
    verdict = judge(Expect(), _outcome(collisions=2))
    assert verdict.failures == ("max_collisions: 2 > 0",)


def test_a_bound_on_something_not_measured_fails() -> None:
    verdict = judge(Expect(max_localization_error=0.5), _outcome(max_localization_error=None))
    assert verdict.failures == ("max_localization_error: not measured (bound 0.5 m)",)


def test_an_event_the_injector_did_not_apply_fails_the_run() -> None:
    assert judge(Expect(), _outcome(), injected=1).failures == ("events: 0 of 1 applied",)
    applied = _outcome(events_applied=("applied kidnap [1, 2, 0] at t=8.00 s",))
    assert judge(Expect(), applied, injected=1).passed


def test_a_runner_error_fails_before_any_criterion() -> None:
    verdict = judge(Expect(result=None, max_collisions=None), Outcome("ERROR", "worker crashed"))
    assert verdict.failures == ("run: worker crashed",)


def test_an_outcome_survives_its_json_round_trip() -> None:
    original = _outcome(events_applied=("applied kidnap",), artifacts={"mcap": "/x.mcap"}, exit_code=1)
    assert Outcome.from_json(original.to_json()) == original


def test_machine_lines_give_result_state_tag_code_and_sim_time() -> None:
    facts = outcome.machine_facts(DEMO_SUCCESS, 0)
    assert (facts.result, facts.final_state, facts.tag, facts.result_code, facts.sim_time) == \
        ("SUCCESS", "StFinalState", "SUCCESS", 0, 43.0)
    facts = outcome.machine_facts(DEMO_ABORT, 1)
    assert (facts.result, facts.tag, facts.result_code, facts.sim_time) == ("ABORT", "ABORT", 208, 14.9)
    assert facts.detail.startswith("ABORT: StNavigateToWaypoint1")


def test_only_the_last_transition_gives_the_result_code() -> None:
    lines = ["[patrol] [t=3.00 s] StA -> StB [ABORT] on EvActionAborted[ClNav2Z, OrNav] (error_code 104: x)",
             "[patrol] [t=9.00 s] StB -> StC [SUCCESS] on EvActionSucceeded[ClNav2Z, OrNav]",
             "[patrol] result: SUCCESS"]
    assert outcome.machine_facts(lines, 0).result_code == 0


def test_the_patrol_summary_gives_its_sim_time() -> None:
    lines = ["[patrol] rounds 1, recharges 0, sim 24.6 s, wall 20.1 s", "[patrol] result: SUCCESS"]
    facts = outcome.machine_facts(lines, 0)
    assert (facts.result, facts.sim_time) == ("SUCCESS", 24.6)


def test_without_a_result_line_the_exit_code_decides() -> None:
    assert outcome.machine_facts([], 2).result == "TIMEOUT"
    assert outcome.machine_facts([], 3).result == "STACK"
    assert outcome.machine_facts(["[patrol] result: the stack stopped (exit code 1)"], 3).result == "STACK"


def test_goal_driver_lines_give_success_error_code_and_sim_time() -> None:
    ok = ["goal 1: result: SUCCEEDED (error_code 0) in 3.10 s sim", "goals: 1 of 1 reached; sim 3.20 s"]
    facts = outcome.goal_facts(ok, 0)
    assert (facts.result, facts.result_code, facts.sim_time) == ("SUCCESS", 0, 3.2)
    assert facts.detail == "1 goals reached"
    failed = ["goal 1: result: SUCCEEDED (error_code 0) in 3.10 s sim",
              "goal 2: result: ABORTED (error_code 208): no path in 0.40 s sim",
              "goals: 1 of 2 reached; sim 3.50 s"]
    facts = outcome.goal_facts(failed, 1)
    assert (facts.result, facts.result_code) == ("ABORT", 208)
    assert facts.detail == "goal 2: result: ABORTED (error_code 208): no path in 0.40 s sim"
    assert outcome.goal_facts(failed[:1], None).result == "TIMEOUT"


def test_tree_lines_give_the_last_cycle() -> None:
    lines = ["[INFO] cycle 1: root FAILURE at 'GoToStation' in 3.0 s (battery 0 %)",
             "[INFO] cycle 2: root SUCCESS in 31.0 s (battery 80 %)"]
    assert outcome.tree_facts(lines, 0).result == "SUCCESS"
    failed = outcome.tree_facts(lines[:1], 0)
    assert (failed.result, failed.tag) == ("ABORT", "FAILURE")
    assert failed.detail == "cycle 1: root FAILURE at 'GoToStation'"


def _scenario(mission: dict[str, object], **fields: object) -> object:
    document = {"scenarios": [{"name": "s", "mission": mission, **fields}]}
    return parse_scenarios(document, "f.yaml", REPO / "config", REPO)[0]


def test_the_seed_machine_runs_through_navsuite_demo_with_world_and_start(tmp_path: Path) -> None:
    scenario = _scenario({"state_machine": "sm_nav2_test_1", "parameters": {"waypoint_1": [1, 0, 0]}},
                         start=[-2, -0.5, 0], world="turtlebot3_world", timeout=50)
    plan = commands.plan(scenario, tmp_path, REPO)  # type: ignore[arg-type]
    assert plan.kind == "machine" and not plan.record and plan.stack is None
    assert plan.mission is not None and plan.mission[0].endswith("navsuite-demo")
    assert plan.mission[plan.mission.index("--timeout") + 1] == "50"
    bringup = plan.mission[plan.mission.index("--bringup") + 1]
    assert "--world turtlebot3_world --x=-2 --y=-0.5 --yaw=0" in bringup
    assert "--participant SmNav2Test1" in bringup
    params = yaml.safe_load(plan.files[tmp_path / "sm_nav2_test_1.yaml"])["SmNav2Test1"]["ros__parameters"]
    assert params["waypoint_1"] == [1.0, 0.0, 0.0] and params["initial_pose"] == [-2.0, -0.5, 0.0]
    assert params["waypoint_2"] == [-0.55, 0.55, 3.141592653589793]  # config/sm_nav2_test_1.yaml's


def test_a_battery_event_becomes_a_sim2d_overlay_over_the_patrol_one(tmp_path: Path) -> None:
    scenario = _scenario({"state_machine": "sm_battery_patrol", "cycles": 2},
                         events=[{"at": 0, "battery": 0.1}])
    plan = commands.plan(scenario, tmp_path, REPO)  # type: ignore[arg-type]
    assert plan.record and plan.mission is not None
    assert plan.mission[plan.mission.index("--cycles") + 1] == "2"
    overlay = yaml.safe_load(plan.files[tmp_path / "sim2d_overlay.yaml"])["sim2d"]["ros__parameters"]
    assert overlay["battery"] == {"drain_per_meter": 0.02, "drain_per_second": 0.0005, "charge_at": "station",
                                  "initial_charge": 0.1}
    assert "--bringup-arg=--world" in plan.mission


def test_goals_run_through_the_goal_driver_as_the_stack_participant(tmp_path: Path) -> None:
    scenario = _scenario({"goals": [[1, 2, 0], [3, 4, -1.5]]})
    plan = commands.plan(scenario, tmp_path, REPO)  # type: ignore[arg-type]
    assert plan.stack is not None and plan.record and plan.stack[-2:] == ["--participant", "scenario_goals"]
    assert plan.mission[-4:] == ["navsuite_tools.scenarios.goal_driver",
                                 "[[1.0, 2.0, 0.0], [3.0, 4.0, -1.5]]", "--wait-for", "/ground_truth"]
    assert "--sim-params" not in plan.stack  # no battery event: sim2d's own parameters


def test_a_tree_runs_nav_autonomy_as_the_stack_participant(tmp_path: Path) -> None:
    scenario = _scenario({"behavior_tree": "config/trees/seed_battery_patrol_v3.xml", "max_cycles": 2})
    plan = commands.plan(scenario, tmp_path, REPO)  # type: ignore[arg-type]
    assert plan.stack is not None and plan.stack[-2:] == ["--participant", "autonomy"]
    assert plan.mission is not None and "use_sim_time:=true" in plan.mission
    assert plan.mission[plan.mission.index("--max-cycles") + 1] == "2"


def test_selection_by_substring_or_glob() -> None:
    scenarios = parse_scenarios({"scenarios": [{"name": n, "mission": {"goals": [[0, 0]]}}
                                               for n in ("seed_a", "seed_b", "patrol_a")]}, "f", None, REPO)
    assert [s.name for s in select(scenarios, ["seed"])] == ["seed_a", "seed_b"]
    assert [s.name for s in select(scenarios, ["*_a"])] == ["seed_a", "patrol_a"]
    assert len(select(scenarios, [])) == 3


def test_a_teleport_sim2d_refused_does_not_count_as_applied(tmp_path: Path) -> None:
    from navsuite_tools.scenarios.worker import _applied_events

    (tmp_path / "scenario-events.log").write_text("applied kidnap [0, 0, 0] at t=8.00 s\n")
    assert _applied_events(tmp_path) == ("applied kidnap [0, 0, 0] at t=8.00 s",)
    (tmp_path / "sim2d.log").write_text("[WARN] [sim2d]: sim2d: teleport to Pose2D(x=0.0, y=0.0, yaw=0.0) "
                                        "refused: footprint overlaps an obstacle\n")
    assert _applied_events(tmp_path) == ()


def test_min_clearance_fails_below_its_bound_or_unmeasured_and_passes_at_or_above_it() -> None:
    expect = Expect(min_clearance=0.05)
    assert judge(expect, _outcome(min_clearance=0.05)).passed
    assert judge(expect, _outcome(min_clearance=0.2)).passed
    close = judge(expect, _outcome(min_clearance=0.031))
    assert close.failures == ("min_clearance: 0.031 m < 0.05 m",) and close.criterion == "min_clearance"
    assert judge(expect, _outcome()).failures == ("min_clearance: not measured (bound 0.05 m)",)
    assert judge(Expect(), _outcome()).passed  # no bound: not checked
    assert Outcome.from_json(_outcome(min_clearance=0.07).to_json()).min_clearance == 0.07


def test_parameter_files_reach_nav_bringup_in_order_and_the_clearance_is_recorded(tmp_path: Path) -> None:
    document = {"scenarios": [{"name": "cm", "mission": {"goals": [[1, 2, 0]]},
                               "params": ["config/nav2_params.yaml",
                                          "config/scenarios/collision_monitor_params.yaml"]}]}
    (scenario,) = parse_scenarios(document, "f.yaml", REPO / "config", REPO)
    plan = commands.plan(scenario, tmp_path, REPO)
    assert plan.stack is not None
    flags = [plan.stack[i + 1] for i, arg in enumerate(plan.stack) if arg == "--params"]
    assert flags == [str(REPO / "config" / "nav2_params.yaml"),
                     str(REPO / "config" / "scenarios" / "collision_monitor_params.yaml")]
    assert "/sim2d/clearance" in commands.RECORDED_TOPICS
    patrol_doc = {"scenarios": [{"name": "m", "mission": {"state_machine": "sm_battery_patrol"},
                                 "params": "config/nav2_params.yaml"}]}
    machine = parse_scenarios(patrol_doc, "f.yaml", REPO / "config", REPO)[0]
    patrol = commands.plan(machine, tmp_path, REPO)
    assert f"--bringup-arg={REPO / 'config' / 'nav2_params.yaml'}" in patrol.mission


def test_a_goal_time_limit_reaches_the_goal_driver_and_a_canceled_goal_is_an_abort(tmp_path: Path) -> None:
    scenario = _scenario({"goals": [[1, 2, 0]], "max_goal_time": 20})
    plan = commands.plan(scenario, tmp_path, REPO)  # type: ignore[arg-type]
    assert plan.mission[-2:] == ["--goal-time", "20"]
    lines = ["goal 1: not done after 20 s sim: canceling",
             "goal 1: result: CANCELED (error_code 0) in 20.05 s sim", "goals: 0 of 1 reached; sim 20.10 s"]
    facts = outcome.goal_facts(lines, 1)
    assert (facts.result, facts.result_code, facts.sim_time) == ("ABORT", 0, 20.1)
