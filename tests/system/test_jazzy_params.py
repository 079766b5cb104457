"""Nav2 Jazzy's own nav2_params.yaml, unmodified (config/jazzy/), runs the seed mission.

What a Nav2 user brings: MPPI as FollowPath, the smoother server, and the velocity chain controller →
/cmd_vel_nav → velocity_smoother → /cmd_vel_smoothed → collision_monitor → /cmd_vel, with the
lifecycle lists coming from bringup (Nav2's file has none). The mission is the SMACC2 tutorial's
(navsuite-demo); its machine selects Nav2's goal checker id ``general_goal_checker`` instead of
SMACC2's ``goal_checker`` (config/sm_nav2_test_1_jazzy.yaml; Nav2's file is left as it is).

The run's recording holds each stage of the velocity chain: the smoother's output must keep Jazzy's
limits (velocity, acceleration, deceleration) at every sample.

Slow: the whole simulator and stack, one mission (about 45 s of sim time).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

pytest.importorskip("nav_stack.ros.bringup.nav_bringup", reason="the stack does not exist yet")

from nav_stack.core.velocity_smoother import VelocitySmootherParams, check_command_series
from navsuite_testing.ros import REPO, SYSTEM_RTF
from navsuite_tools.bag.reader import BagReader
from smacc_py.state_machines.sm_nav2_test_1 import NOMINAL_TRANSITIONS

pytestmark = [pytest.mark.slow, pytest.mark.ros]

JAZZY = REPO / "config" / "jazzy" / "nav2_params.yaml"
MACHINE_PARAMS = REPO / "config" / "sm_nav2_test_1_jazzy.yaml"


def _smoother_params() -> VelocitySmootherParams:
    """velocity_smoother's section of Nav2's file, as the node reads it."""
    section = yaml.safe_load(JAZZY.read_text())["velocity_smoother"]["ros__parameters"]
    fields = set(VelocitySmootherParams.__dataclass_fields__)
    values = {k: tuple(v) if isinstance(v, list) else v for k, v in section.items() if k in fields}
    return VelocitySmootherParams(**values)


def _series(bag: Path, topic: str) -> list[tuple[float, float, float]]:
    """(vx, vy, wz) of every message on ``topic`` (Twist or TwistStamped), in the order published."""
    samples = []
    with BagReader(bag) as reader:
        for _message, msg in reader.decoded([topic]):
            twist = getattr(msg, "twist", msg)
            samples.append((twist.linear.x, twist.linear.y, twist.angular.z))
    return samples


@pytest.mark.timeout(900)
def test_the_seed_mission_succeeds_on_nav2_jazzys_own_parameter_file(tmp_path: Path) -> None:
    report = tmp_path / "demo_report.png"
    cmd = [sys.executable, "-m", "smacc_py.state_machines.sm_nav2_test_1.demo", "--rtf", SYSTEM_RTF,
           "--timeout", "600", "--nav-params", str(JAZZY), "--params-file", str(MACHINE_PARAMS),
           "--report", str(report), "--log-dir", str(tmp_path / "logs")]
    done = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-5000:] + done.stderr[-8000:]
    transitions = [line.split("] ", 2)[-1].split(" on ")[0] for line in done.stdout.splitlines()
                   if line.startswith("[demo] [t=")]
    assert transitions == [f"{s} -> {t} [{tag}]" for s, t, tag in NOMINAL_TRANSITIONS]
    # Nav2's pipeline ran, not the project's own one: MPPI, and every server of Jazzy's launch file
    log = (tmp_path / "logs" / "nav2.log").read_text()
    assert "controllers: FollowPath (MPPIController)" in log
    for server in ("smoother_server", "velocity_smoother", "collision_monitor", "docking_server"):
        assert f"[lifecycle_manager_navigation]: Activating {server}" in log, server
    # the velocity chain, stage by stage, as recorded
    bag = report.with_suffix(".mcap")
    smoothed = _series(bag, "/cmd_vel_smoothed")
    assert len(smoothed) > 200 and max(v for v, _, _ in smoothed) > 0.2, len(smoothed)
    # from the first recorded sample: the recorder finds the topic by discovery, a few messages late
    violations = check_command_series(smoothed[1:], _smoother_params(), start=smoothed[0])
    assert violations == [], "\n".join(str(v) for v in violations[:10])
    assert len(_series(bag, "/cmd_vel_nav")) > 200
    assert len(_series(bag, "/cmd_vel")) > 200
