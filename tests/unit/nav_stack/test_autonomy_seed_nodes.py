"""The seed's node types (nav_stack.ros.autonomy.seed_nodes) on the real seed tree, without ROS."""

from __future__ import annotations

from pathlib import Path

import pytest

from nav_stack.core.bt import BehaviorTreeFactory, BtLoadError, NodeStatus, Tree
from nav_stack.ros.autonomy.battery import CounterBattery, RechargeState, TopicBattery, TopicBatteryParams
from nav_stack.ros.autonomy.locations import Location
from nav_stack.ros.autonomy.seed_nodes import SeedContext, register_seed_nodes
from navsuite_testing.autonomy.fakes import FakeNavigator, ListLog, StepClock

REPO = Path(__file__).resolve().parents[3]
V3 = REPO / "config" / "trees" / "seed_battery_patrol_v3.xml"
V4 = REPO / "config" / "trees" / "seed_battery_patrol_v4.xml"
LOCATIONS = {name: Location(name, *pose) for name, pose in {
    "location1": (-1.03, -0.51, 0.0), "location2": (-0.56, -1.03, 0.0), "location3": (-1.43, -1.34, 3.14),
    "location4": (-1.58, -1.48, 3.14), "station": (-1.37, -0.82, 0.0)}.items()}
SEED_CYCLE = ["location1", "location2", "location3", "location4", "FAILURE",
              "station", "wait", "recharge", "SUCCESS"]
TICK = 0.5


def build(tree_file: Path, navigator: FakeNavigator, battery: object,
          **kwargs: object) -> tuple[Tree, SeedContext]:
    ctx = SeedContext(navigator, battery, LOCATIONS, log=ListLog(), **kwargs)  # type: ignore[arg-type]
    factory = BehaviorTreeFactory()
    register_seed_nodes(factory, ctx)
    return factory.create_tree_from_file(tree_file), ctx


def run_cycles(tree: Tree, ctx: SeedContext, cycles: int, max_ticks: int = 2000) -> list[str]:
    """Tick every 0.5 s until ``cycles`` root results; the trace with root results interleaved."""
    events: list[str] = []
    done = 0
    for tick in range(max_ticks):
        before = len(ctx.trace)
        status = tree.tick_once(tick * TICK)
        events.extend(ctx.trace[before:])
        if status.is_completed:
            events.append(status.value)
            done += 1
            if done == cycles:
                return events
    raise AssertionError(f"only {done} cycles in {max_ticks} ticks: {events}")


@pytest.mark.parametrize("tree_file", [V3, V4], ids=["v3", "v4"])
def test_counter_battery_reproduces_the_seed_sequence_twice(tree_file: Path) -> None:
    navigator = FakeNavigator()
    tree, ctx = build(tree_file, navigator, CounterBattery())
    assert run_cycles(tree, ctx, 4) == SEED_CYCLE * 2
    assert [g.location.name for g in navigator.goals] == ["location1", "location2", "location3", "location4",
                                                          "station"] * 2


def test_wait_seconds_waits_thirty_seconds_of_tree_time_without_blocking() -> None:
    tree, _ctx = build(V3, FakeNavigator(travel_ticks=1), CounterBattery(level=0))
    wait = tree.find("recharge_wait")[0]
    start = None
    for tick in range(200):
        tree.tick_once(tick * TICK)
        if wait.status is NodeStatus.RUNNING and start is None:
            start = tick * TICK
        if start is not None and wait.status is not NodeStatus.RUNNING:
            assert tick * TICK - start == pytest.approx(30.0)
            return
    raise AssertionError("WaitSeconds never finished")


def test_aborted_goal_fails_the_node_and_the_patrol() -> None:
    tree, ctx = build(V3, FakeNavigator(scripts=["aborted"]), CounterBattery())
    statuses = [tree.tick_once(t * TICK) for t in range(4)]
    assert statuses == [NodeStatus.RUNNING] * 3 + [NodeStatus.FAILURE]
    assert any("go_to_location1: goal to location1 aborted (error_code 204" in line for line in ctx.log.lines)
    assert ctx.battery.level == 100  # type: ignore[attr-defined]  # no leg was counted


def test_rejected_goal_fails_instead_of_running_forever() -> None:
    tree, _ = build(V3, FakeNavigator(scripts=["rejected"]), CounterBattery())
    assert tree.tick_once(0.0) is NodeStatus.RUNNING
    assert tree.tick_once(0.5) is NodeStatus.FAILURE


def test_halting_go_to_pose_cancels_its_goal() -> None:
    navigator = FakeNavigator(scripts=["hold"])
    tree, _ = build(V3, navigator, CounterBattery())
    tree.tick_once(0.0)
    tree.tick_once(0.5)
    tree.halt()
    assert navigator.goals[0].cancelled


def test_missing_server_fails_after_the_timeout_with_a_clear_log() -> None:
    clock = StepClock()
    navigator = FakeNavigator(ready=False)
    tree, ctx = build(V3, navigator, CounterBattery(), server_timeout=5.0, wall_clock=clock)
    assert tree.tick_once(0.0) is NodeStatus.RUNNING
    clock.t = 4.0
    assert tree.tick_once(0.5) is NodeStatus.RUNNING
    clock.t = 5.5
    assert tree.tick_once(1.0) is NodeStatus.FAILURE
    assert not navigator.goals
    assert any("action server 'navigate_to_pose' not available after 5 s" in line for line in ctx.log.lines)


def test_late_server_is_used_once_it_appears() -> None:
    clock = StepClock()
    navigator = FakeNavigator(ready=False)
    tree, _ = build(V3, navigator, CounterBattery(), wall_clock=clock)
    tree.tick_once(0.0)
    navigator.ready = True
    tree.tick_once(0.5)
    assert [g.location.name for g in navigator.goals] == ["location1"]


def test_topic_battery_semantics() -> None:
    battery = TopicBattery(TopicBatteryParams(low_threshold=0.2, charged_threshold=0.95,
                                              recharge_timeout=60.0))
    assert not battery.ready() and not battery.is_low() and not battery.has_charge()
    battery.update(0.5)
    assert battery.ready() and not battery.is_low() and battery.has_charge()
    battery.decrement()
    assert battery.charge == 0.5
    battery.update(0.2)
    assert battery.is_low() and not battery.has_charge()
    assert battery.start_recharge(100.0) is RechargeState.CHARGING
    battery.update(0.96)
    assert battery.poll_recharge(120.0) is RechargeState.CHARGED
    battery.update(0.5)
    assert battery.start_recharge(200.0) is RechargeState.CHARGING
    assert battery.poll_recharge(261.0) is RechargeState.FAILED


def test_topic_battery_rejects_inconsistent_thresholds() -> None:
    with pytest.raises(ValueError, match="low_threshold < charged_threshold"):
        TopicBatteryParams(low_threshold=0.9, charged_threshold=0.5)


def test_topic_battery_runs_the_seed_order_when_the_threshold_is_crossed_on_the_last_leg() -> None:
    battery = TopicBattery()
    battery.update(1.0)
    navigator = FakeNavigator(travel_ticks=2)
    tree, ctx = build(V3, navigator, battery)
    events: list[str] = []
    for tick in range(400):
        if navigator.goals and navigator.goals[-1].location.name == "location4":
            battery.update(0.15)  # the simulator drained below 20 % on the way to location4
        if ctx.trace[-1:] == ["wait"]:
            battery.update(1.0)  # charged while parked
        before = len(ctx.trace)
        status = tree.tick_once(tick * TICK)
        events.extend(ctx.trace[before:])
        if status.is_completed:
            events.append(status.value)
            if status is NodeStatus.SUCCESS:
                break
    assert events == SEED_CYCLE


def test_unknown_node_is_a_one_line_load_error(tmp_path: Path) -> None:
    bad = tmp_path / "tree.xml"
    bad.write_text(V3.read_text().replace("<RechargeBattery", "<RechargeBatery"))
    with pytest.raises(BtLoadError) as info:
        build(bad, FakeNavigator(), CounterBattery())
    message = str(info.value)
    assert "\n" not in message and str(bad) in message and "RechargeBatery" in message
