"""nav-goal: waypoint file validation, and goto / waypoints in a child process against a scripted
navigate_to_pose (exit status, result line with error code and message, Ctrl-C cancels)."""

from __future__ import annotations

import re
import signal
from collections.abc import Iterator
from pathlib import Path

import pytest

from nav_stack.ros.tools.goal_cli import load_waypoints
from navsuite_testing.ros import REPO, BackgroundSpin, start_python, stop_process, wait_until


def test_example_waypoints_load():
    points = load_waypoints(REPO / "config" / "waypoints_example.yaml")
    assert points[0] == (-0.55, -1.65, 0.0) and len(points) == 4


@pytest.mark.parametrize(("text", "message"), [
    ("[]", "non-empty list"),
    ("- [1.0]\n", "waypoint 0: expected [x, y] or [x, y, yaw]"),
    ("- [1.0, 2.0]\n- [a, 2.0]\n", "waypoint 1"),
    ("waypoints:\n  - [1.0, .nan]\n", "not finite"),
])
def test_bad_waypoint_files_name_the_file_and_index(tmp_path: Path, text, message):
    path = tmp_path / "w.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=re.escape(message)) as info:
        load_waypoints(path)
    assert str(path) in str(info.value)


@pytest.fixture
def navigator(ros_context) -> Iterator[object]:
    from rclpy.executors import MultiThreadedExecutor

    from tests.helpers.nav_ros_bt_fakes import FakeNavigateToPose

    node = FakeNavigateToPose(context=ros_context)
    executor = MultiThreadedExecutor(num_threads=4, context=ros_context)
    executor.add_node(node)
    spin = BackgroundSpin(executor)
    try:
        yield node
    finally:
        spin.stop(node)


@pytest.mark.ros
def test_goto_prints_the_result_exits_by_outcome_and_ctrl_c_cancels(navigator):
    ok = start_python("nav_stack.ros.tools.goal_cli", ["goto", "1.0", "2.0", "0.5"])
    assert ok.wait(timeout=60) == 0, stop_process(ok)
    assert "result: SUCCEEDED (error_code 0)" in ok.stdout.read()
    navigator.failing.add((3.0, 1.0))
    failed = start_python("nav_stack.ros.tools.goal_cli", ["goto", "3.0", "1.0"])
    assert failed.wait(timeout=60) == 1
    assert "result: ABORTED (error_code 208): scripted failure" in failed.stdout.read()

    # Ctrl-C cancels the goal (same server: a fresh one per test could be shadowed by the last
    # test's server until DDS notices it left).
    navigator.goals.clear()
    navigator.hold = True
    proc = start_python("nav_stack.ros.tools.goal_cli", ["goto", "1.0", "0.0"])
    try:
        wait_until(lambda: len(navigator.goals) == 1, 60.0, "the goal to arrive")
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=30) == 130
    finally:
        stop_process(proc)  # a failed test leaves no client behind
    assert navigator.canceled == 1
