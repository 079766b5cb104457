"""autonomy_node over rclpy: the seed's tree.xml against a scripted navigate_to_pose server (and a
scripted /battery_state), two full cycles in the seed's order, cancel on halt, abort, config errors."""

from __future__ import annotations

import signal
import subprocess
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from nav2_msgs.msg import BehaviorTreeLog
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import BatteryState

from nav_stack.core.bt import NodeStatus
from nav_stack.ros.autonomy.locations import load_locations, nearest_location
from nav_stack.ros.autonomy.node import AutonomyNode
from navsuite_testing.ros import REPO, spin_until, start_python, wait_until
from ros_tools.runtime.executor import make_executor
from tests.helpers.smacc_ros_fake_nav2 import FakeNav2

pytestmark = pytest.mark.ros

V3 = REPO / "config" / "trees" / "seed_battery_patrol_v3.xml"
LOCATIONS = load_locations(REPO / "config" / "locations.yaml")
SEED_VISITS = ["location1", "location2", "location3", "location4", "station"]


@dataclass
class Rig:
    fake: FakeNav2
    node: AutonomyNode
    probe: Node
    executor: Executor
    bt_logs: list[BehaviorTreeLog]

    def visited(self) -> list[str | None]:
        goals = self.fake.logs["navigate_to_pose"].goals
        return [nearest_location(LOCATIONS.values(), g.pose.pose.position.x, g.pose.pose.position.y, 1e-6)
                for g in goals]


def start(context: Any, scripts: dict[str, list[str]] | None = None, executor_kind: str = "events",
          **params: Any) -> Rig:
    fake = FakeNav2(context, scripts=scripts, clock_rate=20.0).start()
    overrides = [Parameter("use_sim_time", value=True), Parameter("server_timeout", value=20.0)]
    overrides += [Parameter(k, value=v) for k, v in params.items()]
    node = AutonomyNode(context=context, parameter_overrides=overrides)
    probe = Node("autonomy_probe", context=context)
    logs: list[BehaviorTreeLog] = []
    probe.create_subscription(BehaviorTreeLog, "/behavior_tree_log", logs.append, 100)
    executor = make_executor(executor_kind, context)
    executor.add_node(node)
    executor.add_node(probe)
    return Rig(fake, node, probe, executor, logs)


@pytest.fixture
def rigs(ros_context) -> Iterator[list[Rig]]:
    made: list[Rig] = []
    try:
        yield made
    finally:
        for rig in made:
            rig.executor.shutdown(timeout_sec=1.0)
            rig.node.destroy_node()
            rig.probe.destroy_node()
            rig.fake.stop()


@pytest.mark.parametrize("executor_kind", ["events", "single"])
def test_seed_tree_runs_two_full_cycles_in_the_seed_order(ros_context, rigs, executor_kind):
    rig = start(ros_context, executor_kind=executor_kind, battery_source="counter", max_cycles=4,
                tree_file=str(V3))
    rigs.append(rig)
    spin_until(rig.executor, lambda: rig.node.finished, 60.0, "four root results")
    assert rig.visited() == SEED_VISITS * 2
    assert rig.node.cycle_results == [NodeStatus.FAILURE, NodeStatus.SUCCESS] * 2
    assert rig.node.seed.trace == ["location1", "location2", "location3", "location4",
                                      "station", "wait", "recharge"] * 2
    spin_until(rig.executor, lambda: any(e.node_name == "check_battery4" and e.current_status == "FAILURE"
                                         for log in rig.bt_logs for e in log.event_log), 5.0,
               "check_battery4 FAILURE on /behavior_tree_log")


def test_halting_the_tree_cancels_the_running_goal(ros_context, rigs):
    rig = start(ros_context, {"navigate_to_pose": ["hold"]}, battery_source="counter")
    rigs.append(rig)
    nav = rig.fake.logs["navigate_to_pose"]
    spin_until(rig.executor, lambda: len(nav.goals) == 1, 20.0, "the first goal")
    spin_until(rig.executor, lambda: rig.node.tree.find("go_to_location1")[0].status is NodeStatus.RUNNING,
               5.0, "GoToPose RUNNING")
    rig.node.stop()
    spin_until(rig.executor, lambda: nav.cancels == 1, 10.0, "the cancel request")
    spin_until(rig.executor, lambda: nav.results == ["canceled"], 10.0, "the goal to end canceled")


def test_aborted_goal_fails_go_to_pose_and_the_root(ros_context, rigs):
    rig = start(ros_context, {"navigate_to_pose": ["aborted"]}, battery_source="counter", max_cycles=1)
    rigs.append(rig)
    spin_until(rig.executor, lambda: rig.node.finished, 20.0, "one root result")
    assert rig.node.cycle_results == [NodeStatus.FAILURE]
    assert rig.node.seed.trace == []
    spin_until(rig.executor, lambda: any(e.node_name == "go_to_location1" and e.current_status == "FAILURE"
                                         for log in rig.bt_logs for e in log.event_log), 5.0,
               "go_to_location1 FAILURE on /behavior_tree_log")


def test_topic_battery_recharges_until_the_simulator_reports_charged(ros_context, rigs):
    rig = start(ros_context, battery_source="topic", max_cycles=1, recharge_timeout=600.0)
    rigs.append(rig)
    pub = rig.probe.create_publisher(BatteryState, "/battery_state", 10)
    level = {"value": 0.1}

    def publish() -> None:
        pub.publish(BatteryState(percentage=level["value"]))

    rig.probe.create_timer(0.02, publish)
    recharge = rig.node.tree.find("recharge_battery")[0]
    spin_until(rig.executor, lambda: recharge.status is NodeStatus.RUNNING, 30.0, "RechargeBattery RUNNING")
    started = rig.node.get_clock().now().nanoseconds * 1e-9
    spin_until(rig.executor, lambda: rig.node.get_clock().now().nanoseconds * 1e-9 > started + 5.0, 10.0,
               "5 s more of sim time")
    assert recharge.status is NodeStatus.RUNNING and not rig.node.cycle_results  # still charging at 10 %
    level["value"] = 0.97
    spin_until(rig.executor, lambda: rig.node.finished, 20.0, "the recharge to finish")
    assert rig.node.cycle_results == [NodeStatus.SUCCESS]
    assert rig.visited() == ["station"]


def run_node(*params: str) -> subprocess.CompletedProcess[str]:
    args = ["--ros-args"] + [a for p in params for a in ("-p", p)]
    proc = start_python("nav_stack.ros.autonomy.node", args)
    try:
        out, _ = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, "")


def test_unknown_node_in_the_tree_exits_2_with_one_line(tmp_path: Path):
    bad = tmp_path / "tree.xml"
    bad.write_text(V3.read_text().replace('<IsBatteryLow name="check_if_low" />', '<IsBatteryEmpty/>'))
    result = run_node(f"tree_file:={bad}")
    assert result.returncode == 2, result.stdout
    errors = [line for line in result.stdout.splitlines() if line.startswith("autonomy_node:")]
    assert errors == [f"autonomy_node: {bad}:5: <IsBatteryEmpty>: unknown node type 'IsBatteryEmpty' "
                      "(not registered in the factory)"], result.stdout


def test_missing_location_exits_2_with_one_line(tmp_path: Path):
    locations = tmp_path / "locations.yaml"
    locations.write_text("".join(f"location{i}: [{i}, 0, 0]\n" for i in range(1, 5)))
    result = run_node(f"location_file:={locations}")
    assert result.returncode == 2, result.stdout
    errors = [line for line in result.stdout.splitlines() if line.startswith("autonomy_node:")]
    assert len(errors) == 1 and errors[0].startswith(
        f"autonomy_node: {locations}: location 'station' used by GoToPose 'go_to_station'"), result.stdout


def test_main_ends_by_itself_after_max_cycles(ros_context):
    """``python -m nav_stack.ros.autonomy.node`` on the default EventsExecutor: the seed's first cycle
    against the fake (four legs, then CheckBattery fails), then a clean exit 0."""
    fake = FakeNav2(ros_context, clock_rate=20.0).start()
    try:
        result = run_node("battery_source:=counter", "max_cycles:=1", "use_sim_time:=true",
                          "server_timeout:=30.0", f"tree_file:={V3}")
    finally:
        fake.stop()
    assert result.returncode == 0, result.stdout
    assert "cycle 1: root FAILURE at 'check_battery4'" in result.stdout, result.stdout
    assert "finished 1 cycles; visited: location1, location2, location3, location4" in result.stdout
    assert "Traceback" not in result.stdout, result.stdout


def test_sigterm_cancels_the_running_goal_and_exits(ros_context):
    """A launcher stops the node with SIGTERM in the middle of a goal: the goal is cancelled and the
    process exits 0 (with rclpy's own handlers the context shut down first, and one such process
    spun on for an hour)."""
    fake = FakeNav2(ros_context, clock_rate=20.0, frozen=True).start()  # the goal never completes
    args = ["--ros-args", "-p", "battery_source:=counter", "-p", "use_sim_time:=true",
            "-p", "server_timeout:=30.0", "-p", f"tree_file:={V3}"]
    proc = start_python("nav_stack.ros.autonomy.node", args)
    try:
        wait_until(lambda: bool(fake.logs["navigate_to_pose"].goals), 60.0, "the first goal")
        proc.send_signal(signal.SIGTERM)
        out, _ = proc.communicate(timeout=30)
        assert proc.returncode == 0, out
        wait_until(lambda: fake.logs["navigate_to_pose"].cancels >= 1, 10.0, "the goal's cancel")
        assert "Traceback" not in out, out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        fake.stop()
