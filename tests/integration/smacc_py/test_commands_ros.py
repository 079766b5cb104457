"""The commands as processes: smacc-run, smacc-key, smacc-graph and navsuite-demo (on a fake stack)."""

from __future__ import annotations

import subprocess
import sys

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import SmaccStatus, SmaccTransitionLogEntry

from navsuite_testing.ros import REPO, spin_until, start_python, stop_process
from smacc_py.state_machines.sm_nav2_test_1 import NOMINAL_TRANSITIONS
from tests.helpers.smacc_ros_fake_nav2 import FakeNav2

pytestmark = pytest.mark.ros

LOG_QOS = QoSProfile(
    depth=100, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
# in lockstep with the machine, as nav-bringup's simulator is: a free-running clock let a loaded machine's
# CbPureSpinning read its odometry late and turn 372 of 180 degrees (CI run 17)
FAKE_STACK = f"{sys.executable} {REPO / 'tests/helpers/smacc_ros_fake_nav2.py'} --lockstep SmNav2Test1"


def _key(entry: SmaccTransitionLogEntry) -> tuple[str, str, str]:
    t = entry.transition
    return t.source_state_name, t.destiny_state_name, t.transition_type


def test_smacc_run_and_smacc_key_drive_the_machine_across_processes(ros_context) -> None:  # type: ignore[no-untyped-def]
    # No bonds and a clock that stands still: StAllSensorsGo's 15 s (sim) timer never fires, so only
    # key N can leave it, however long the key's process takes to start and discover the machine.
    # The key goes once the machine's status names StAllSensorsGo: its keyboard behavior listens only
    # from its state's entry, and /keyboard_unicode is subscribed earlier, when the client is built.
    fake = FakeNav2(ros_context, bond_nodes=(), clock_rate=0.0).start()
    probe = rclpy.create_node("run_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    log: list[SmaccTransitionLogEntry] = []
    probe.create_subscription(
        SmaccTransitionLogEntry, "/SmNav2Test1/smacc/transition_log", log.append, LOG_QOS
    )
    states: list[str] = []
    probe.create_subscription(
        SmaccStatus, "/SmNav2Test1/smacc/status", lambda msg: states.extend(msg.current_states), LOG_QOS
    )
    proc = start_python("smacc_py.ros.runner", ["sm_nav2_test_1", "--ros-args", "-p", "use_sim_time:=true"])
    output = ""
    try:
        spin_until(
            executor,
            lambda: "StAllSensorsGo" in states or proc.poll() is not None,
            30.0,
            "smacc-run's status to name StAllSensorsGo",
        )
        assert proc.poll() is None
        key = subprocess.run(
            [sys.executable, "-m", "smacc_py.clients.cl_keyboard.send_key", "n"],
            cwd=REPO,
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert key.returncode == 0, key.stderr
        spin_until(
            executor, lambda: bool(log), 20.0, "the first transition on /SmNav2Test1/smacc/transition_log"
        )
        assert _key(log[0]) == ("StAllSensorsGo", "StSetInitialPose", "NEXT")
        assert log[0].transition.event.label == "EvKeyPressN[CbDefaultKeyboardBehavior, OrKeyboard]"
    finally:
        output = stop_process(proc)
        executor.shutdown()
        probe.destroy_node()
        fake.stop()
    assert "StAllSensorsGo -> StSetInitialPose [NEXT]" in output


def test_smacc_key_fails_when_nobody_listens() -> None:
    key = subprocess.run(
        [
            sys.executable,
            "-m",
            "smacc_py.clients.cl_keyboard.send_key",
            "n",
            "--wait",
            "0.5",
            "--topic",
            "/nobody_listens_here",
        ],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert key.returncode == 1
    assert "nobody subscribes /nobody_listens_here" in key.stderr


def test_smacc_graph_exports_mermaid_from_declarations(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "sm.mmd"
    done = subprocess.run(
        [sys.executable, "-m", "smacc_py.ros.graph_cli", "sm_nav2_test_1", "-o", str(out)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    text = out.read_text()
    assert (
        "StAllSensorsGo --> StSetInitialPose : EvCbSuccess[CbWaitNav2Nodes, OrNavigation] / NAV2_READY"
        in text
    )
    bad = subprocess.run(
        [sys.executable, "-m", "smacc_py.ros.graph_cli", "no_such_machine"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert bad.returncode == 2
    assert "shipped machines: no smacc_py.state_machines.no_such_machine" in bad.stderr


@pytest.mark.parametrize(
    ("extra", "code", "expected"),
    [
        ([], 0, [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS] + ["result: SUCCESS"]),
        (
            ["--abort-navigation"],
            1,
            [
                "StNavigateToWaypoint1 -> StFinalState [ABORT]",
                "error_code 204: fake navigate_to_pose aborted as scripted",
                "result: ABORT",
            ],
        ),
    ],
)
def test_demo_reports_the_mission_and_exits_with_its_result(extra, code, expected, tmp_path) -> None:  # type: ignore[no-untyped-def]
    bringup = " ".join([FAKE_STACK, *extra])
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "smacc_py.state_machines.sm_nav2_test_1.demo",
            "--rtf",
            "10",
            "--timeout",
            "60",
            "--bringup",
            bringup,
            "--waypoint1",
            "1.0,0.5,0.0",
            "--report",  # not artifacts/demo_report.*, which belong to the real stack's run
            str(tmp_path / "report.png"),
        ],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == code, done.stdout + done.stderr
    for line in expected:
        assert line in done.stdout, done.stdout
    assert "waypoint_1 (1.0, 0.5, 0.0)" in done.stdout
    assert "states visited: StAllSensorsGo -> StSetInitialPose" in done.stdout
