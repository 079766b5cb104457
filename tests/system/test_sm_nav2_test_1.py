"""navsuite-demo against the real stack (sim2d + nav_stack via ``nav-bringup``): the tutorial end to end.

The successful run is also the check of what the demo leaves behind, so no second full run is paid:
its run report (printed path, a PNG that shows the run; copied to artifacts/) and its recording,
which ``navsuite-bag play`` must put back on the graph with the topics and counts ``info`` lists.
Reports go to the test's tmp_path, so tests never overwrite a user's artifacts/demo_report.*.

Slow: it starts the whole simulator and navigation stack. Skipped until
nav_stack.ros.bringup.nav_bringup exists.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from rclpy.context import Context

pytest.importorskip("nav_stack.ros.bringup.nav_bringup",
                    reason="nav-bringup (nav_stack.ros.bringup.nav_bringup) does not exist yet")

from nav_stack.ros.bringup import nav_bringup as bringup
from navsuite_testing.ros import REPO, SYSTEM_RTF
from navsuite_tools.report.render import AMCL_COLOR, TRUTH_COLOR
from smacc_py.state_machines.sm_nav2_test_1 import NOMINAL_TRANSITIONS
from smacc_py.state_machines.sm_nav2_test_1.demo import REPLAY_TOPICS
from tests.helpers.bag_replay import bag_info, play_and_count
from tests.helpers.report_pixels import content_fraction, distinct_colors, load_rgb, pixels_near

pytestmark = [pytest.mark.slow, pytest.mark.ros]

#: The mission's ~40 s of recording replay in ~10 s; the player and the counter keep up with that.
REPLAY_RATE = "4"
ARTIFACT = REPO / "artifacts" / "test_demo_report.png"


def _demo(report: Path, *args: str, cwd: Path = REPO,
          timeout: float = 900.0) -> subprocess.CompletedProcess[str]:
    """``navsuite-demo`` with its default (calm) console, piped as in CI; the logs go to the session's
    NAVSUITE_LOG_DIR (tests/conftest.py) unless the caller's ``cwd`` should hold them."""
    cmd = [sys.executable, "-m", "smacc_py.state_machines.sm_nav2_test_1.demo", "--rtf", SYSTEM_RTF,
           "--report", str(report), *args]
    env = dict(os.environ)
    if cwd != REPO:
        env.pop("NAVSUITE_LOG_DIR", None)  # the default then: <cwd>/artifacts/logs
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def _transitions(stdout: str) -> list[str]:
    return [
        line.split("] ", 2)[-1].split(" on ")[0]
        for line in stdout.splitlines()
        if line.startswith("[demo] [t=")
    ]


def _check_report(stdout: str, report: Path) -> None:
    """The report's path is printed, and the PNG shows a run rather than an empty frame."""
    assert f"[demo] run report: {report.resolve()}" in stdout.splitlines(), stdout[-3000:]
    ARTIFACT.parent.mkdir(exist_ok=True)
    shutil.copyfile(report, ARTIFACT)  # kept for a look when a pixel count below fails
    rgb = load_rgb(report)
    assert distinct_colors(rgb) > 50
    assert content_fraction(rgb) > 0.04  # a report of an empty recording has about 0.02
    assert (rgb < 40).all(axis=2).mean() > 0.01  # the map's walls
    # a successful run of this mission draws about 850 ground-truth and 2000 AMCL pixels
    assert pixels_near(rgb, TRUTH_COLOR) > 400
    assert pixels_near(rgb, AMCL_COLOR) > 400


def _check_replay(bag: Path, context: Context) -> None:
    """``play`` of the demo's recording yields exactly the topics and counts ``info`` lists.

    The demo's processes have all exited, so the test's ROS domain holds only the player and the
    fresh context's counter. Counts are compared exactly, latched topics (/map, /tf_static,
    /amcl_pose) included: every subscription is matched before the player starts (it waits for
    subscribers), all recorded topics are reliable, and the player waits for every message to be
    acknowledged before it exits.
    """
    recorded = {topic: count for topic, (_type, count) in bag_info(bag).items()}
    assert set(REPLAY_TOPICS) <= recorded.keys(), recorded
    # what the robot sensed and did is there (/local_plan stays empty under a controller without a
    # local trajectory, such as Regulated Pure Pursuit)
    assert all(recorded[topic] > 0 for topic in ("/scan", "/odom", "/tf", "/tf_static", "/cmd_vel")), recorded
    replay = play_and_count(context, bag, list(recorded), recorded, ["--rate", REPLAY_RATE],
                            timeout=180.0)
    assert replay.returncode == 0, replay.output
    assert replay.counts == recorded


@pytest.mark.timeout(900)
def test_demo_completes_the_mission_through_success(tmp_path: Path, ros_context: Context) -> None:
    """Run from a directory outside the repository, as a user might: the console is the story (five
    transitions and a summary in under 40 lines) and every process's full log is in artifacts/logs."""
    report = tmp_path / "demo_report.png"
    done = _demo(report, "--timeout", "600", cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-5000:] + done.stderr[-8000:]
    assert _transitions(done.stdout) == [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS]
    assert "result: SUCCESS" in done.stdout
    assert len(done.stdout.splitlines()) < 40, done.stdout
    assert "[demo] ---------------- summary ----------------" in done.stdout
    logs = tmp_path / "artifacts" / "logs"
    # one log per process of the stack, whichever layout it runs in ($NAVSUITE_LAYOUT)
    stack = [spec.name for spec in bringup.process_specs(bringup.parse_args([]))]
    assert {"nav.log", "record.log"} | {f"{name}.log" for name in stack} <= {
        log.name for log in logs.glob("*.log")}, done.stdout
    # the full log of the navigation nodes' process (nav2 or navigation), INFO lines too
    assert "Managed nodes are active" in (logs / f"{stack[-1]}.log").read_text()
    _check_report(done.stdout, report)
    _check_replay(report.with_suffix(".mcap"), ros_context)


@pytest.mark.timeout(900)
def test_waypoint_beyond_the_outer_wall_aborts_with_the_planners_error(tmp_path: Path) -> None:
    """The planner's refusal reaches the console. Without a recording: the report of an aborted run is
    tests/integration/smacc_py/test_commands_ros.py's (fake stack); here it cost a quarter of the CPU."""
    done = _demo(tmp_path / "demo_report.png", "--timeout", "600", "--waypoint1", "5.0,3.0,1.57",
                 "--no-report")
    assert done.returncode == 1, done.stdout[-5000:] + done.stderr[-8000:]
    transitions = _transitions(done.stdout)
    assert transitions[:2] == [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS[:2]]
    assert transitions[-1] == "StNavigateToWaypoint1 -> StFinalState [ABORT]"
    abort_line = next(line for line in done.stdout.splitlines() if "StFinalState [ABORT]" in line)
    # the planner's Nav2 error code and message reach the output (docs/demo.md quotes this line)
    assert "error_code 208: 'compute_path_to_pose' failed with error code 208 (NO_VALID_PATH)" in abort_line
    assert "result: ABORT" in done.stdout
    # the calm console hides the stack's output, but not the warnings that explain a failure
    problems = done.stdout.split("[demo] the stack's last", 1)[-1]
    assert "[bt_navigator]: navigate_to_pose: goal failed" in problems, done.stdout[-5000:]


@pytest.mark.timeout(900)
def test_demo_runs_the_mission_with_a_tb4(tmp_path: Path) -> None:
    """``--robot tb4`` reaches nav-bringup: the TurtleBot4's simulation and parameters do the same mission."""
    done = _demo(tmp_path / "demo_report.png", "--timeout", "600", "--robot", "tb4", "--no-report")
    assert done.returncode == 0, done.stdout[-5000:] + done.stderr[-8000:]
    assert "--robot tb4" in done.stdout.splitlines()[0]  # "[demo] starting the stack: ..."
    assert _transitions(done.stdout) == [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS]


@pytest.mark.timeout(900)
def test_upstreams_second_waypoint_in_a_pillar_succeeds_within_the_planner_tolerance(tmp_path: Path) -> None:
    """(0, 0) is inside turtlebot3_world's middle pillar. NavFn's 0.5 m tolerance plans to the nearest
    reachable point instead, so the goal succeeds, as it does with Nav2 (docs/demo.md says so)."""
    done = _demo(tmp_path / "demo_report.png", "--timeout", "600", "--waypoint2", "0,0,0",
                 "--no-report")
    assert done.returncode == 0, done.stdout[-5000:] + done.stderr[-8000:]
    assert _transitions(done.stdout) == [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS]
