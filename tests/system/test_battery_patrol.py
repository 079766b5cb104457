"""The battery patrol against the real stack (``nav-bringup``: sim2d + nav_stack).

* autonomy_node runs the seed's tree.xml with the counter battery for two full cycles (four
  locations, root FAILURE, station, wait, recharge, root SUCCESS, twice): the visited sequence is
  the seed's;
* sm_battery_patrol, driven by sim2d's simulated battery, does two rounds with recharges and resumes
  the interrupted leg. To get recharges within two rounds, the low threshold sits just under a full
  charge (0.95) and charged at 0.99: with the demo's config/sim2d_battery_patrol.yaml sim2d drains
  2 % per metre, a round is about 3.5 m, and it charges 2 % per s parked within 0.4 m of the station.

Slow. Skipped until nav_stack.ros.bringup.nav_bringup exists.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

pytest.importorskip("nav_stack.ros.bringup.nav_bringup",
                    reason="nav-bringup (nav_stack.ros.bringup.nav_bringup) does not exist yet")

from navsuite_testing.autonomy.system import run_autonomy, set_initial_pose, start_stack
from navsuite_testing.ros import REPO, SYSTEM_RTF

pytestmark = [pytest.mark.slow, pytest.mark.ros]

SEED_TRACE = ["location1", "location2", "location3", "location4", "station", "wait", "recharge"] * 2


def test_autonomy_node_runs_the_seed_tree_twice_in_the_simulator() -> None:
    launcher = start_stack(SYSTEM_RTF)
    try:
        set_initial_pose()
        params = {"battery_source": "counter", "max_cycles": 4, "server_timeout": 60.0}
        # 240 s wall (about 140 s of sim time, 15-20 s wall in lockstep at rtf max): a stuck run
        # fails with the node's output, inside the suite's 300 s limit.
        run = run_autonomy(params, timeout=240.0)
    finally:
        launcher.shutdown()  # type: ignore[attr-defined]
    # Warnings and errors first (a failed goal names its error code there), then the output's end,
    # then the stack's warnings (the controller's and behaviors' reasons, with sim times).
    report = "\n".join(line for line in run.output.splitlines() if "[WARN]" in line or "[ERROR]" in line)
    report += "\n...\n" + run.output[-3000:]
    stack_warnings = [line for line in launcher.lines if "WARN" in line or "ERROR" in line]  # type: ignore[attr-defined]
    report += "\n--- stack warnings ---\n" + "\n".join(stack_warnings[-60:])
    assert run.returncode == 0, report
    assert [result for result, _ in run.cycles()] == ["FAILURE", "SUCCESS"] * 2, report
    assert run.visited() == SEED_TRACE, report


def test_sm_battery_patrol_does_two_rounds_on_the_simulated_battery() -> None:
    cmd = [sys.executable, "-m", "smacc_py.state_machines.sm_battery_patrol.demo", "--rtf", SYSTEM_RTF,
           "--cycles", "2", "--low-threshold", "0.95", "--charged-threshold", "0.99", "--timeout", "240"]
    # The demo's own 240 s wall limit (about 10 s at rtf max) ends a stuck run with its output, inside
    # the suite's 300 s limit (a robot wedged at location3 once ran on until pytest killed it, silently).
    result = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=280)
    out = result.stdout
    assert result.returncode == 0, out[-4000:]
    assert "[patrol] result: SUCCESS" in out
    assert "[LOW_BATTERY]" in out and "[RESUME]" in out and "(history)" in out, out[-4000:]
