"""nav-goal against a scripted Nav2 (tests/helpers/smacc_ros_fake_nav2.py), on both executors.

The CLI runs as a child process, as a user runs it: ``goto`` must print the result and exit 0 on
success and 1 on an abort; ``initial-pose`` adds the initial pose publisher to the CLI's executor
and removes it again once the fake AMCL confirms the pose.
"""

from __future__ import annotations

import subprocess
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.action")

from navsuite_testing.ros import start_python
from tests.helpers.smacc_ros_fake_nav2 import FakeNav2

pytestmark = pytest.mark.ros


def nav_goal(*args: str) -> subprocess.CompletedProcess[str]:
    proc = start_python("nav_stack.ros.tools.goal_cli", args)
    try:
        out, _ = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, "")


@pytest.mark.parametrize("executor_kind", ["events", "single"])
def test_goto_prints_the_result_and_its_exit_code(ros_context: Any, executor_kind: str) -> None:
    fake = FakeNav2(ros_context, scripts={"navigate_to_pose": ["succeeded", "aborted"]},
                    clock_rate=20.0).start()
    try:
        done = nav_goal("--executor", executor_kind, "goto", "0.5", "0.0")
        aborted = nav_goal("--executor", executor_kind, "goto", "1.0", "0.0", "1.57")
    finally:
        fake.stop()
    assert done.returncode == 0, done.stdout
    assert "result: SUCCEEDED" in done.stdout and "Traceback" not in done.stdout, done.stdout
    assert aborted.returncode == 1, aborted.stdout
    assert "result: ABORTED" in aborted.stdout, aborted.stdout
    goals = fake.logs["navigate_to_pose"].goals
    assert [round(g.pose.pose.position.x, 3) for g in goals] == [0.5, 1.0]


def test_initial_pose_waits_for_amcl_then_exits_0(ros_context: Any) -> None:
    fake = FakeNav2(ros_context, clock_rate=20.0).start()
    try:
        result = nav_goal("initial-pose", "-1.5", "0.5", "0.3")
    finally:
        fake.stop()
    assert result.returncode == 0, result.stdout
    assert "initial pose confirmed by AMCL" in result.stdout, result.stdout
    assert fake.initial_poses and fake.initial_poses[-1] == pytest.approx((-1.5, 0.5, 0.3), abs=1e-6)
