"""sm_dance_bot against the real stack (``nav-bringup``: sim2d + nav_stack in lockstep) with its support
nodes: one whole run of the demo.

The run must end in StFinalState through the SUCCESS path, and the transitions the machine publishes on its
introspection topic (``/SmDanceBot/smacc/transition_log``, smacc2_msgs/SmaccTransitionLogEntry, as the other
reference machines' tests read them) must be, one by one and in order, those SMACC2's sm_dance_bot declares
(tests/helpers/dance_bot_sequence.py: the tables written from the upstream headers, and why the check is a
walk through them: a motion the behavior server refuses takes its declared failure transition). So every
looping superstate runs all of its iterations, every pattern ends with its ENDLOOP, and the scripted
overheating of the temperature sensor (sim 60 to 66 s) takes the machine into MsDanceBotRecoveryMode and,
through deep history, back into the very state it left. The demo's own report must agree: the loop counters
on the machine's blackboard, the recovery mode's entries and exits, the number of transitions. The machine's
LED service calls (std_srvs/SetBool) must reach the LED server, switching it on and off.

The check itself is tested in tests/unit/smacc_py/test_dance_bot_sequence.py: the walk refuses a transition
missing, extra or out of order.

Slow: about a minute of wall time on two idle cores (one run of the demo), several on a loaded machine.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav_stack.ros.bringup.nav_bringup",
                    reason="nav-bringup (nav_stack.ros.bringup.nav_bringup) does not exist yet")

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import SmaccTransitionLogEntry
from std_msgs.msg import Bool

from navsuite_testing.ros import REPO, SYSTEM_RTF, spin_until
from smacc_py.state_machines.sm_dance_bot.support_nodes import LED_STATE_TOPIC
from tests.helpers.dance_bot_sequence import LOOPS, RECOVERED, SequenceMismatch, check_sequence

LOOPS_LINE = re.compile(r"\[demo\] loops: (.*)")
RECOVERY = re.compile(r"\[demo\] recovery mode: entered (\d+), left (\d+)")
TRANSITIONS = re.compile(r"\[demo\] transitions: (\d+);")
EXPECTED_LOOPS = {loop.superstate: f"{loop.iterations}/{loop.iterations}" for loop in LOOPS}
TRANSITION_LOG = "/SmDanceBot/smacc/transition_log"
WALL_S = 870.0  # wall s the whole demo may take (its own --timeout is 780 s for the dance)


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.timeout(900)
def test_sm_dance_bot_takes_upstreams_transitions_dances_every_pattern_recovers_and_ends(
    ros_context: Any, tmp_path: Path,
) -> None:
    node = rclpy.create_node("dance_bot_transition_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    log: list[SmaccTransitionLogEntry] = []
    # The log's QoS (smacc_py/ros/introspection.py); a deep queue: a run takes about 90 transitions.
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(SmaccTransitionLogEntry, TRANSITION_LOG, log.append, qos)
    led: list[Bool] = []  # the LED server republishes each SetBool request it answers
    node.create_subscription(Bool, LED_STATE_TOPIC, led.append, qos)
    cmd = [sys.executable, "-m", "smacc_py.state_machines.sm_dance_bot.demo", "--rtf", SYSTEM_RTF,
           "--timeout", "780"]
    stdout, stderr = tmp_path / "demo.out", tmp_path / "demo.err"
    try:
        with stdout.open("w") as out_file, stderr.open("w") as err_file:
            process = subprocess.Popen(cmd, cwd=REPO, stdout=out_file, stderr=err_file, text=True)
            try:
                spin_until(executor, lambda: process.poll() is not None, WALL_S, "the demo's end", step=0.1)
            finally:
                if process.poll() is None:
                    process.kill()
                    process.wait()
        out = stdout.read_text()
        tail = out[-6000:] + stderr.read_text()[-3000:]
        assert process.returncode == 0, tail
        assert "[demo] result: SUCCESS" in out, tail
        reported = TRANSITIONS.search(out)
        assert reported is not None, tail
        count = int(reported.group(1))
        # Each entry went out when its transition was taken, long before the demo's end; spin for stragglers.
        spin_until(executor, lambda: len(log) >= count, 10.0, f"{count} entries on {TRANSITION_LOG}")
    finally:
        executor.shutdown()
        node.destroy_node()

    keys = [(e.transition.source_state_name, e.transition.destiny_state_name, e.transition.transition_type)
            for e in log]
    assert len(keys) == count, (keys, tail)
    try:
        walk = check_sequence(keys)
    except SequenceMismatch as error:  # names the first transition the definition does not declare there
        pytest.fail(f"{error}\n--- the demo's output (the reasons of failed motions):\n{tail}")
    assert keys[-1] == ("StNavigateToWaypoint1", "StFinalState", "SUCCESS"), keys[-3:]
    assert walk.recoveries >= 1, keys  # the scripted overheating
    assert all(e.transition.history_node == (key == RECOVERED) for e, key in zip(log, keys, strict=True))
    # The services: the machine's ClLED calls (std_srvs/SetBool on /led_control) reached the LED server.
    assert {True, False} <= {msg.data for msg in led}, led

    loops = LOOPS_LINE.search(out)
    assert loops is not None, tail
    counts = dict(item.split("=") for item in loops.group(1).split(", "))
    assert counts == EXPECTED_LOOPS, tail
    recovery = RECOVERY.search(out)
    assert recovery is not None, tail
    assert int(recovery.group(1)) == int(recovery.group(2)) == walk.recoveries, tail
