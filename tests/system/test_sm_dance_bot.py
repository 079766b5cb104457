"""sm_dance_bot against the real stack (``nav-bringup``: sim2d + nav_stack in lockstep) with its support
nodes: one whole run of the demo.

The run must end in StFinalState through the SUCCESS path; every looping superstate must have run all
of its iterations (the loop counters on the machine's blackboard, printed by the demo); the scripted
overheating of the temperature sensor (sim 60 to 66 s) must take the machine into
MsDanceBotRecoveryMode and back into the run mode through deep history. The demo's transition lines
must show the same: an OVERHEAT transition into the recovery mode, a RECOVERED one out of it, and
every pattern's ENDLOOP.

Slow: a few minutes of wall time on two cores.
"""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

pytest.importorskip("nav_stack.ros.bringup", reason="nav-bringup (nav_stack.ros.bringup) does not exist yet")

from navsuite_testing.ros import REPO, SYSTEM_RTF

pytestmark = [pytest.mark.slow, pytest.mark.ros]

LOOPS = re.compile(r"\[demo\] loops: (.*)")
RECOVERY = re.compile(r"\[demo\] recovery mode: entered (\d+), left (\d+)")
EXPECTED_LOOPS = {"SsRadialPattern1": "2/2", "SsRadialPattern2": "4/4", "SsRadialPattern3": "2/2",
                  "SsFPattern1": "2/2", "SsSPattern1": "2/2"}


@pytest.mark.timeout(900)
def test_sm_dance_bot_dances_every_pattern_recovers_from_overheating_and_ends() -> None:
    cmd = [sys.executable, "-m", "smacc_py.state_machines.sm_dance_bot.demo", "--rtf", SYSTEM_RTF,
           "--timeout", "780"]
    result = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=870)
    out = result.stdout
    tail = out[-6000:]
    assert result.returncode == 0, tail
    assert "[demo] result: SUCCESS" in out, tail
    loops = LOOPS.search(out)
    assert loops is not None, tail
    counts = dict(item.split("=") for item in loops.group(1).split(", "))
    assert counts == EXPECTED_LOOPS, tail
    recovery = RECOVERY.search(out)
    assert recovery is not None and int(recovery.group(1)) >= 1, tail
    assert recovery.group(1) == recovery.group(2), tail
    assert re.search(r"-> MsDanceBotRecoveryMode \[OVERHEAT\]", out), tail
    assert re.search(r"MsDanceBotRecoveryMode -> \w+ \[RECOVERED\]", out), tail
    for superstate in EXPECTED_LOOPS:
        assert re.search(rf"{superstate} -> \w+ \[ENDLOOP\]", out), (superstate, tail)
    assert re.search(r"StNavigateToWaypoint1 -> StFinalState \[SUCCESS\]", out), tail
