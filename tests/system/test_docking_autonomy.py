"""The seed's docking tree end to end: nav-autonomy runs config/trees/seed_battery_patrol_docking.xml
(with config/autonomy_docking.yaml's parameters) against nav-bringup with turtlebot3_world's dock
database and the docking patrols' sim2d battery (config/autonomy_docking.yaml's sim2d section: 2 % per
metre, charged on the dock's contacts only), started at 22 % so that the first round runs low, and
drained by distance only (_sim_params says why).

Three cycles: the patrol stops at a CheckBattery (root FAILURE); the tree docks at home_dock
(DockRobot, staging navigation included), sim2d reports CHARGING with base_link on the contacts and the
charge rises to ``charged_threshold`` (RechargeBattery), UndockRobot backs off to the staging pose
(root SUCCESS); then the patrol goes on and completes a round (root SUCCESS). Observed: the node's
cycle lines and trace, docking_server's results in the stack's log, /battery_state and sim2d's ground
truth (a probe in this process).

Slow. Skipped until nav_stack.ros.bringup.nav_bringup exists.
"""

from __future__ import annotations

import math
import re
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml

pytest.importorskip("nav_stack.ros.bringup.nav_bringup",
                    reason="nav-bringup (nav_stack.ros.bringup.nav_bringup) does not exist yet")

from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from sensor_msgs.msg import BatteryState
from std_msgs.msg import UInt32

from navsuite_testing.autonomy.system import run_autonomy, set_initial_pose, start_stack
from navsuite_testing.ros import REPO, SYSTEM_RTF, BackgroundSpin

pytestmark = [pytest.mark.slow, pytest.mark.ros]

AUTONOMY_FILE = REPO / "config" / "autonomy_docking.yaml"
DOCK_FILE = REPO / "config" / "docks" / "turtlebot3_world.yaml"
CONTACT = (-0.55, -2.29, -1.5708)  # home_dock's contact pose in map (sim2d/worlds/turtlebot3_world.yaml)
INITIAL_CHARGE = 0.22  # 1 m of patrol (2 %/m) above low_threshold 0.2: the first leg or two run it low
#: Not the file's 0.95: 0.5 is enough for a whole round (about 4 m, 8 %) and charges in about 16 s of sim
#: time instead of 40. The rule under test (charge until the threshold, then undock) is the same.
CHARGED = 0.5
PATROL = ["location1", "location2", "location3", "location4"]
CHARGING = BatteryState.POWER_SUPPLY_STATUS_CHARGING


class Probe:
    """/battery_state, sim2d's ground truth and collision count, recorded from a background thread."""

    def __init__(self, context: Any) -> None:
        self.node = Node("docking_autonomy_probe", context=context)
        self._lock = threading.Lock()
        self.truth: tuple[float, float, float] | None = None
        self.collisions = 0
        #: (charge, charging, ground truth then) per /battery_state message
        self.battery: list[tuple[float, bool, tuple[float, float, float] | None]] = []
        self.node.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        self.node.create_subscription(BatteryState, "/battery_state", self._on_battery, 10)
        self.node.create_subscription(UInt32, "/sim2d/collision_count", self._on_collisions, 10)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(self.node)
        self.spin = BackgroundSpin(executor, "docking autonomy probe")

    def _on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        with self._lock:
            self.truth = (p.x, p.y, 2.0 * math.atan2(q.z, q.w))

    def _on_battery(self, msg: BatteryState) -> None:
        with self._lock:
            self.battery.append((float(msg.percentage), msg.power_supply_status == CHARGING, self.truth))

    def _on_collisions(self, msg: UInt32) -> None:
        self.collisions = msg.data

    def close(self) -> None:
        self.spin.stop(self.node)


@pytest.fixture
def probe(ros_context: Any) -> Iterator[Probe]:
    probe = Probe(ros_context)
    try:
        yield probe
    finally:
        probe.close()


def _sim_params(tmp_path: Path) -> Path:
    """config/autonomy_docking.yaml's sim2d section, starting at INITIAL_CHARGE, drained by distance only.

    Why no drain per second: sim time runs while the stack starts and AMCL takes the initial pose, for
    as long as the machine's load makes it (one run idled 80 s and started the tree at 18 %, below
    low_threshold, so it docked before patrolling). Driving alone drains the same in every run.
    """
    sim = yaml.safe_load(AUTONOMY_FILE.read_text())["sim2d"]
    sim["ros__parameters"]["battery"].update(initial_charge=INITIAL_CHARGE, drain_per_second=0.0)
    path = tmp_path / "sim2d_docking.yaml"
    path.write_text(yaml.safe_dump({"sim2d": sim}))
    return path


def test_the_seed_docking_tree_docks_charges_undocks_and_patrols_on(tmp_path: Path, probe: Probe) -> None:
    logs = tmp_path / "logs"
    bringup = ["--params", str(REPO / "config" / "nav2_params.yaml"), "--params", str(DOCK_FILE),
               "--sim-params", str(_sim_params(tmp_path)), "--log-dir", str(logs)]
    launcher = start_stack(SYSTEM_RTF, bringup)
    try:
        set_initial_pose()
        params = yaml.safe_load(AUTONOMY_FILE.read_text())["autonomy_node"]["ros__parameters"]
        params.update(max_cycles=3, charged_threshold=CHARGED, server_timeout=60.0)
        # 200 s wall at most (about 150 s of sim time; some 30 s wall at rtf max): a stuck run fails
        # with the node's output, inside the suite's 300 s limit.
        run = run_autonomy(params, timeout=200.0)
    finally:
        launcher.shutdown()  # type: ignore[attr-defined]
    stack_log = "\n".join(path.read_text() for path in sorted(logs.glob("*.log")))
    report = "\n".join(line for line in run.output.splitlines() if "[WARN]" in line or "[ERROR]" in line)
    report += "\n...\n" + run.output[-3000:] + "\n--- stack ---\n"
    report += "\n".join(line for line in stack_log.splitlines()
                        if "dock" in line.lower() or "WARN" in line or "ERROR" in line)[-4000:]

    # the tree: low battery ends the first round, the second cycle docks and charges, the third patrols
    assert run.returncode == 0, report
    assert [result for result, _ in run.cycles()] == ["FAILURE", "SUCCESS", "SUCCESS"], report
    assert re.search(r"cycle 1: root FAILURE at 'check_battery\d'", run.output), report
    visited = run.visited()
    assert visited.count("recharge") == 1 and visited[-5:] == ["recharge", *PATROL], report
    assert visited[0] == "location1", report
    # docking_server: one docking and one undocking, both succeeded, in that order. A retry within the
    # docking is allowed: Nav2's loop retries a lost detection (seen once in 8 runs on a loaded machine:
    # the last detection 1.02 s old at external_detection_timeout 1 s), and the docking then succeeds.
    results = re.findall(r"(dock_robot|undock_robot) (succeeded|failed.*)", stack_log)
    assert results == [("dock_robot", "succeeded"), ("undock_robot", "succeeded")], report
    contacts = re.search(r"charging on home_dock at sim time [\d.]+ s \(base_link (\d+) mm", stack_log)
    assert contacts is not None and int(contacts.group(1)) <= 50, report  # contact_tolerance 0.05 m

    # sim2d: CHARGING only on the contacts, while the charge rose from <= low to >= CHARGED
    battery = list(probe.battery)
    charging = [(charge, truth) for charge, on, truth in battery if on]
    assert charging, report
    before = [charge for charge, on, _ in battery[:next(i for i, b in enumerate(battery) if b[1])]]
    assert min(before) <= params["low_threshold"], (min(before), report)
    assert max(charge for charge, _ in charging) >= CHARGED - 0.02, report  # battery_rate sampling
    for _, truth in charging[1:]:  # the first may precede the truth message of the docked pose
        assert truth is not None
        assert math.hypot(truth[0] - CONTACT[0], truth[1] - CONTACT[1]) < 0.05, truth  # contact_tolerance
    # after charging: undocked and away on the patrol, no collision on the way
    after = battery[max(i for i, b in enumerate(battery) if b[1]) + 1:]
    assert after and not any(on for _, on, _ in after)
    final = probe.truth
    assert final is not None and math.hypot(final[0] - CONTACT[0], final[1] - CONTACT[1]) > 1.0, final
    assert probe.collisions == 0, report
    print(f"\ncycles {run.cycles()}, visited {visited}, wall {run.wall_s:.1f} s; charge "
          f"{min(before):.3f} -> {max(c for c, _ in charging):.3f} on the dock")
