"""A user's own machine from scratch: ``smacc-new`` writes it in a folder outside the repository, ruff and
its own test pass, ``smacc-graph <path>`` draws it, ``smacc-run <path>`` runs it on the ROS graph, its
transitions arrive on the SMACC2 introspection topic, and Ctrl-C ends the run with exit status 0 and no
traceback.

One test, as it starts processes: the scaffold, ruff, the package's pytest, the graph and the machine.
"""

from __future__ import annotations

import shutil
import signal
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import SmaccTransitionLogEntry
from std_msgs.msg import String

from navsuite_testing.ros import REPO, spin_until

pytestmark = [pytest.mark.slow, pytest.mark.ros]

#: The transition log's QoS (smacc_py/ros/introspection.py): a late subscriber still gets the entries.
LOG = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: The project's own ruff rules, applied to the package as a user's checkout would see it.
RUFF_RULES = ["--select", "E,F,W,I,B,UP,SIM,RUF,N", "--ignore", "N802,N815", "--line-length", "88"]


def _command(script: str, module: str) -> list[str]:
    """The console script of this environment, or ``python -m`` its module before a reinstall made it."""
    exe = Path(sys.executable).parent / script
    return [str(exe)] if exe.exists() else [sys.executable, "-m", module]


def _run(cmd: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=120)


@pytest.mark.timeout(240)
def test_smacc_new_package_runs_by_path_and_stops_quietly(tmp_path: Path, ros_context: Any) -> None:
    assert REPO not in tmp_path.parents
    made = _run([*_command("smacc-new", "smacc_py.scaffold"), "sm_probe_machine"], tmp_path)
    assert made.returncode == 0, made.stderr
    assert "run it:   smacc-run ./sm_probe_machine" in made.stdout
    again = _run([*_command("smacc-new", "smacc_py.scaffold"), "sm_probe_machine"], tmp_path)
    assert again.returncode == 2 and "already exists; not overwriting it" in again.stderr

    ruff = shutil.which("ruff") or str(Path(sys.executable).parent / "ruff")
    for extra in ([], ["--isolated", *RUFF_RULES]):  # ruff's defaults, then the project's rules
        checked = _run([ruff, "check", *extra, "sm_probe_machine"], tmp_path)
        assert checked.returncode == 0, checked.stdout
    tested = _run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "sm_probe_machine/tests"],
                  tmp_path)
    assert tested.returncode == 0 and "1 passed" in tested.stdout, tested.stdout
    graph = _run([*_command("smacc-graph", "smacc_py.ros.graph_cli"), "./sm_probe_machine"], tmp_path)
    assert graph.returncode == 0 and "StState1" in graph.stdout, graph.stderr

    probe = rclpy.create_node("smacc_new_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    log: list[SmaccTransitionLogEntry] = []
    beats: list[str] = []
    prefix = "/SmProbeMachine"
    probe.create_subscription(SmaccTransitionLogEntry, f"{prefix}/smacc/transition_log", log.append, LOG)
    probe.create_subscription(String, f"{prefix}/heartbeat", lambda msg: beats.append(msg.data),  # type: ignore[attr-defined]
                              10)
    run = subprocess.Popen([*_command("smacc-run", "smacc_py.ros.runner"), "./sm_probe_machine"],
                           cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        spin_until(executor, lambda: len(log) >= 2, 60.0, "two transitions on the transition log")
        transitions = [(t.source_state_name, t.destiny_state_name, t.transition_type, t.event.event_type,
                        t.event.event_source, t.event.event_object_tag)
                       for t in (entry.transition for entry in log[:2])]
        loop = ("StState1", "StState1", "SUCCESS", "EvCbSuccess", "CbBeat", "OrHeartbeat")
        assert transitions == [loop, loop]
        assert "beat 3/3" in beats  # what made the transition, heard on the machine's own topic
        run.send_signal(signal.SIGINT)
        assert run.wait(timeout=30) == 0
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
        executor.shutdown()
        probe.destroy_node()
    out = run.stdout.read() if run.stdout else ""
    assert "StState1: beating" in out  # the state's get_logger() is the node's logger
    assert "StState1 -> StState1 [SUCCESS] on EvCbSuccess[CbBeat, OrHeartbeat]" in out
    assert "Traceback" not in out and "KeyboardInterrupt" not in out, out
