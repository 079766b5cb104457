"""sm_battery_patrol on the real ROS runtime against FakeNav2 and a scripted /battery_state: patrol,
a low reading sends it to recharge mode, a charged reading resumes the interrupted location."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import pytest
from rclpy.node import Node
from sensor_msgs.msg import BatteryState

from navsuite_testing.ros import wait_until
from smacc_py.state_machines.sm_battery_patrol import VISITS_KEY, SmBatteryPatrol

pytestmark = pytest.mark.ros

SEED_XY = {(-1.03, -0.51): "location1", (-0.56, -1.03): "location2", (-1.43, -1.34): "location3",
           (-1.58, -1.48): "location4", (-1.37, -0.82): "station"}


class ScriptedBattery:
    """Publishes ``level`` (0..1) on /battery_state every 20 ms (wall) from its own thread."""

    def __init__(self, context: object, level: float) -> None:
        self.level = level
        self.node = Node("scripted_battery", context=context)  # type: ignore[arg-type]
        self._pub = self.node.create_publisher(BatteryState, "/battery_state", 10)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(0.02):
            self._pub.publish(BatteryState(percentage=self.level))

    def close(self) -> None:
        self._stop.set()
        self._thread.join(1.0)
        self.node.destroy_node()


@pytest.fixture
def battery(ros_context: object) -> Iterator[ScriptedBattery]:
    scripted = ScriptedBattery(ros_context, 0.8)
    try:
        yield scripted
    finally:
        scripted.close()


def leaf(runtime) -> str:  # type: ignore[no-untyped-def]
    names = runtime.sm.current_state_names()
    return names[-1] if names else ""


def test_low_battery_recharges_then_history_resumes_the_interrupted_location(stack, battery) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(SmBatteryPatrol, clock_rate=20.0,
                          scripts={"navigate_to_pose": ["succeeded", "hold", "succeeded", "succeeded"]})
    nav = fake.logs["navigate_to_pose"]
    wait_until(lambda: leaf(runtime) == "StiGoToLocation2" and len(nav.goals) == 2, 30.0,
               "the patrol to be on its way to location2")
    battery.level = 0.1
    wait_until(lambda: leaf(runtime) == "StiCharge", 30.0, "recharge mode to reach the station")
    # The interrupted leg's goal was cancelled. The station's goal leaves as the patrol exits, so the
    # fake may finish it before it has processed that cancel: the order of the two results is the
    # fake's, not the machine's.
    wait_until(lambda: "canceled" in nav.results, 10.0, "the interrupted leg's goal to end")
    assert nav.cancels == 1 and nav.results[0] == "succeeded"
    assert sorted(nav.results[1:3]) == ["canceled", "succeeded"]
    assert leaf(runtime) == "StiCharge"  # still low: it stays parked
    battery.level = 1.0
    wait_until(lambda: len(runtime.sm.get_global_sm_data(VISITS_KEY, [])) >= 4, 30.0,
               "the patrol to resume and reach two more locations")
    records = list(runtime.sm.transition_log)
    got = [(r.source.__name__, r.leaf.__name__, r.tag.__name__, r.history) for r in records[:6]]
    assert got == [
        ("StStartup", "StiGoToLocation1", "SUCCESS", False),
        ("StiGoToLocation1", "StiGoToLocation2", "NEXT", False),
        ("SsPatrol", "StiGoToStation", "LOW_BATTERY", False),
        ("StiGoToStation", "StiCharge", "NEXT", False),
        ("StiCharge", "StiGoToLocation2", "RESUME", True),
        ("StiGoToLocation2", "StiGoToLocation3", "NEXT", False),
    ]
    visited = [SEED_XY.get((round(g.pose.pose.position.x, 2), round(g.pose.pose.position.y, 2)))
               for g in nav.goals[:5]]
    assert visited == ["location1", "location2", "station", "location2", "location3"]
    assert runtime.sm.get_global_sm_data(VISITS_KEY)[:4] == ["location1", "station", "location2", "location3"]
    assert fake.initial_poses and fake.initial_poses[0] == pytest.approx((-2.0, -0.5, 0.0))


def test_patrol_goes_round_the_four_locations_from_parameters(stack, battery) -> None:  # type: ignore[no-untyped-def]
    fake, runtime = stack(SmBatteryPatrol, clock_rate=20.0, params={"location3": [-1.5, -1.3, 3.14]})
    wait_until(lambda: len(fake.logs["navigate_to_pose"].goals) >= 6, 30.0, "six goals")
    xs = [round(g.pose.pose.position.x, 2) for g in fake.logs["navigate_to_pose"].goals[:6]]
    assert xs == [-1.03, -0.56, -1.5, -1.58, -1.03, -0.56]
    wait_until(lambda: runtime.sm.get_global_sm_data("patrol_cycles", 0) >= 1, 10.0, "one full cycle")


def test_demo_runs_two_rounds_with_a_recharge_and_exits_0() -> None:
    import subprocess
    import sys

    from navsuite_testing.ros import start_python

    stack = f"{sys.executable} -m tests.helpers.autonomy_fake_stack --drain 0.15 --charge 0.5"
    proc = start_python("smacc_py.state_machines.sm_battery_patrol.demo",
                        ["--bringup", stack, "--rtf", "10", "--cycles", "2", "--timeout", "120",
                         "--low-threshold", "0.7", "--charged-threshold", "0.9"])
    try:
        out, _ = proc.communicate(timeout=180)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    assert proc.returncode == 0, out
    assert "[patrol] result: SUCCESS" in out
    assert "-> StiGoToStation [LOW_BATTERY]" in out and "[RESUME]" in out and "(history)" in out, out
