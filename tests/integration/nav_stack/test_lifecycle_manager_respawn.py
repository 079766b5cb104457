"""lifecycle manager and a managed node in another process that freezes or dies (issue 45).

The manager runs here; the managed node (amcl) is a child process. A freeze (SIGSTOP) longer than
``bond_timeout`` loses the bond: the manager resets the system, and brings it back up once the
node answers again (SIGCONT), as Nav2's ``attempt_respawn_reconnection`` does. A shorter freeze is
ridden out. A node process killed under ros_tools.launch's ``respawn`` comes back as a new process
and the manager reconnects to it through the bond.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("nav2_msgs.srv")

from lifecycle_msgs.msg import State
from lifecycle_msgs.srv import GetState
from nav2_msgs.srv import ManageLifecycleNodes
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from nav_stack.ros.lifecycle.lifecycle_manager import LifecycleManager
from navsuite_testing.localization.nodes import call
from navsuite_testing.ros import spin_until, start_python, stop_process
from ros_tools.launch import Launcher, ProcessSpec

pytestmark = pytest.mark.ros
BOND_TIMEOUT = 2.0  # s: short, so the tests are quick; the manager's logic does not depend on it
NODE = "amcl_frozen_under_manager"  # names no other test uses (DDS discovery can linger)


class Rig:
    """The manager (and a probe) on one executor in this process; the node in a child process."""

    def __init__(self, context: Any, node: str) -> None:
        self.manager = LifecycleManager(f"lifecycle_manager_{node}", context=context, parameter_overrides=[
            Parameter("node_names", value=[node]), Parameter("bond_timeout", value=BOND_TIMEOUT),
            Parameter("bond_respawn_max_duration", value=60.0), Parameter("service_timeout", value=20.0)])
        self.probe = Node(f"probe_{node}", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        for n in (self.manager, self.probe):
            self.executor.add_node(n)
        self.state = self.probe.create_client(GetState, f"/{node}/get_state")
        self.manage = self.probe.create_client(ManageLifecycleNodes,
                                               f"/lifecycle_manager_{node}/manage_nodes")

    def startup(self) -> None:
        request = ManageLifecycleNodes.Request(command=ManageLifecycleNodes.Request.STARTUP)
        assert call(self.executor, self.manage, request, timeout=60.0, resend_after=None).success

    def node_state(self) -> int:
        return int(call(self.executor, self.state, GetState.Request(), timeout=30.0).current_state.id)

    def spin_until(self, predicate: Any, timeout: float, what: str) -> None:
        spin_until(self.executor, predicate, timeout, what)

    def close(self) -> None:
        self.executor.shutdown()
        for n in (self.manager, self.probe):
            n.destroy_node()


@pytest.fixture
def frozen(ros_context: Any) -> Iterator[tuple[Rig, Any]]:
    proc = start_python("nav_stack.ros.localization.amcl_node", ["--ros-args", "-r", f"__node:={NODE}"])
    rig = Rig(ros_context, NODE)
    try:
        yield rig, proc
    finally:
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGCONT)
        rig.close()
        print(stop_process(proc))


def test_a_freeze_longer_than_the_bond_timeout_resets_the_system_and_sigcont_brings_it_back(
        frozen: tuple[Rig, Any], capfd: Any) -> None:
    rig, proc = frozen
    rig.startup()
    assert rig.manager.system_active
    os.kill(proc.pid, signal.SIGSTOP)
    try:
        rig.spin_until(lambda: not rig.manager.system_active, 30.0, "the manager to notice the lost bond")
        rig.spin_until(lambda: rig.manager._respawn_timer is not None, 30.0, "the reconnection attempts")
    finally:
        os.kill(proc.pid, signal.SIGCONT)
    rig.spin_until(lambda: rig.manager.system_active, 60.0, "the system to be active again after SIGCONT")
    assert rig.node_state() == State.PRIMARY_STATE_ACTIVE
    err = capfd.readouterr().err
    assert f"CRITICAL FAILURE: SERVER {NODE} IS DOWN" in err
    assert "All managed nodes answer again: restarting them" in err
    assert f"Server {NODE} connected with bond." in err


def test_a_freeze_shorter_than_the_bond_timeout_is_ridden_out(frozen: tuple[Rig, Any], capfd: Any) -> None:
    rig, proc = frozen
    rig.startup()
    went_down: list[bool] = []
    os.kill(proc.pid, signal.SIGSTOP)
    try:  # frozen for about a quarter of the bond timeout (wall s), the manager spinning meanwhile
        deadline_polls = int(BOND_TIMEOUT / 4.0 / 0.02)
        for _ in range(deadline_polls):
            rig.executor.spin_once(timeout_sec=0.02)
            went_down.append(not rig.manager.system_active)
    finally:
        os.kill(proc.pid, signal.SIGCONT)
    for _ in range(int(2.0 * BOND_TIMEOUT / 0.02)):  # then two bond timeouts of normal running
        rig.executor.spin_once(timeout_sec=0.02)
        went_down.append(not rig.manager.system_active)
    assert not any(went_down)
    assert rig.node_state() == State.PRIMARY_STATE_ACTIVE
    assert "CRITICAL FAILURE" not in capfd.readouterr().err


def test_a_killed_node_process_is_respawned_and_the_manager_reconnects_through_the_bond(
        ros_context: Any, capfd: Any) -> None:
    node = "amcl_respawned_under_manager"
    launcher = Launcher(output=lambda line: print(line, flush=True), color=False, shutdown_grace=5.0)
    spec = ProcessSpec(node, [sys.executable, "-m", "nav_stack.ros.localization.amcl_node", "--ros-args",
                              "-r", f"__node:={node}"], respawn=True, respawn_delay=0.5)
    rig = Rig(ros_context, node)
    waiter = threading.Thread(target=launcher.wait, daemon=True)
    try:
        launcher.start([spec])
        waiter.start()
        rig.startup()
        first = launcher.running[0].proc.pid
        os.kill(first, signal.SIGKILL)
        rig.spin_until(lambda: launcher.running[0].proc.pid != first, 30.0, "the launcher's respawn")
        rig.spin_until(lambda: not rig.manager.system_active, 30.0, "the manager to notice the lost bond")
        rig.spin_until(lambda: rig.manager.system_active, 90.0, "the manager to bring the new process up")
        assert rig.node_state() == State.PRIMARY_STATE_ACTIVE
    finally:
        launcher.stop()
        waiter.join(5.0)
        launcher.shutdown()
        rig.close()
    out = capfd.readouterr()
    assert f"WARN: {node} died with exit code -9; respawning it" in out.out
    assert f"Server {node} connected with bond." in out.err
