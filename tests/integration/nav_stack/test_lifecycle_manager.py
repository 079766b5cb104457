"""lifecycle manager: manage_nodes commands, is_active, and the bond timeout of a killed node process.

Managed nodes: map_server (in this process) and amcl (a child process). The manager shares a
single-threaded executor with the test, which also shows that its service calls never block it.
"""

from __future__ import annotations

import signal
import time
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
from std_srvs.srv import Trigger

from nav_stack.ros.lifecycle.lifecycle_manager import LifecycleManager
from nav_stack.ros.localization.map_server import MapServer
from navsuite_testing.localization.nodes import MAP_YAML, call
from navsuite_testing.ros import spin_until, start_python, stop_process
from tests.helpers.lossy_service import LoseResponses

pytestmark = pytest.mark.ros
Request = ManageLifecycleNodes.Request
AMCL = "amcl_under_manager"


class Graph:
    def __init__(self, context: Any, bond_timeout: float) -> None:
        # A name no other test uses: a node of an earlier test's context can linger in DDS discovery.
        self.amcl_proc = start_python("nav_stack.ros.localization.amcl_node",
                                      ["--ros-args", "-r", f"__node:={AMCL}"])
        self.map_server = MapServer(context=context,
                                    parameter_overrides=[Parameter("yaml_filename", value=str(MAP_YAML))])
        self.manager = LifecycleManager("lifecycle_manager_test", context=context, parameter_overrides=[
            Parameter("node_names", value=["map_server", AMCL]),
            Parameter("bond_timeout", value=bond_timeout),
            Parameter("attempt_respawn_reconnection", value=False), Parameter("service_timeout", value=20.0)])
        self.probe = Node("manager_probe", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        for node in (self.map_server, self.manager, self.probe):
            self.executor.add_node(node)
        self.manage = self.probe.create_client(ManageLifecycleNodes, "/lifecycle_manager_test/manage_nodes")
        self.is_active = self.probe.create_client(Trigger, "/lifecycle_manager_test/is_active")
        self.amcl_state = self.probe.create_client(GetState, f"/{AMCL}/get_state")

    def command(self, command: int) -> bool:
        # Sent once: a command takes seconds, and a second STARTUP would find the nodes active.
        return bool(call(self.executor, self.manage, Request(command=command), timeout=60.0,
                         resend_after=None).success)

    def active(self) -> bool:
        return bool(call(self.executor, self.is_active, Trigger.Request()).success)

    def states(self) -> tuple[int, int]:
        amcl = call(self.executor, self.amcl_state, GetState.Request(), timeout=30.0).current_state.id
        return self.map_server._state_machine.current_state[0], amcl

    def close(self) -> str:
        self.executor.shutdown()
        for node in (self.map_server, self.manager, self.probe):
            node.destroy_node()
        return stop_process(self.amcl_proc)


@pytest.fixture
def graph(ros_context: Any, request: Any) -> Iterator[Graph]:
    g = Graph(ros_context, getattr(request, "param", 4.0))
    try:
        yield g
    finally:
        print(g.close())  # the amcl child's log, shown when a test fails


ACTIVE, INACTIVE = State.PRIMARY_STATE_ACTIVE, State.PRIMARY_STATE_INACTIVE
UNCONFIGURED, FINALIZED = State.PRIMARY_STATE_UNCONFIGURED, State.PRIMARY_STATE_FINALIZED


def test_manage_nodes_commands_and_is_active(graph: Graph) -> None:
    assert not graph.active()
    assert graph.command(Request.STARTUP)
    assert graph.active() and graph.states() == (ACTIVE, ACTIVE)
    assert graph.command(Request.PAUSE)
    assert not graph.active() and graph.states() == (INACTIVE, INACTIVE)
    assert graph.command(Request.RESUME)
    assert graph.active() and graph.states() == (ACTIVE, ACTIVE)
    assert graph.command(Request.RESET)
    assert not graph.active() and graph.states() == (UNCONFIGURED, UNCONFIGURED)
    assert graph.command(Request.CONFIGURE) and graph.states() == (INACTIVE, INACTIVE)
    assert graph.command(Request.CLEANUP) and graph.states() == (UNCONFIGURED, UNCONFIGURED)
    assert graph.command(Request.STARTUP) and graph.active()
    assert graph.command(Request.SHUTDOWN)
    assert not graph.active()
    assert graph.map_server._state_machine.current_state[0] == FINALIZED


def test_lost_answers_of_a_managed_node_do_not_fail_the_bringup(graph: Graph) -> None:
    """The first get_state and change_state answers of map_server are lost (as rmw_fastrtps loses one
    while discovery still matches): the manager sends again and judges the transition by the state."""
    lost = [LoseResponses(graph.map_server._service_get_state, 1),
            LoseResponses(graph.map_server._service_change_state, 1)]
    assert graph.command(Request.STARTUP)
    assert graph.active() and graph.states() == (ACTIVE, ACTIVE)
    assert [loss.lost for loss in lost] == [1, 1]


@pytest.mark.parametrize("graph", [1.0], indirect=True)
def test_bond_timeout_of_a_killed_node_brings_the_others_down(graph: Graph, capfd: Any) -> None:
    assert graph.command(Request.STARTUP) and graph.active()
    graph.amcl_proc.send_signal(signal.SIGKILL)
    graph.amcl_proc.wait(timeout=10.0)
    log = ""

    def reset_done() -> bool:
        nonlocal log
        log += capfd.readouterr().err
        return "Managed nodes have been reset" in log

    spin_until(graph.executor, reset_done, 30.0, "the manager to react to the lost bond")
    assert f"CRITICAL FAILURE: SERVER {AMCL} IS DOWN after not receiving a heartbeat for 1000 ms" in log
    assert not graph.active()
    assert graph.map_server._state_machine.current_state[0] == UNCONFIGURED


@pytest.mark.parametrize("graph", [1.0], indirect=True)
def test_a_stalled_manager_does_not_blame_its_nodes(graph: Graph, capfd: Any) -> None:
    """The process stops running for 2.5 bond timeouts (here: nobody spins its executor, as when the
    machine is starved or another node's callback holds the thread). map_server, in the same process,
    sent no heartbeat meanwhile and amcl's wait unread: on resuming, the manager gives them a whole
    bond_timeout to be heard again instead of taking a live stack down."""
    assert graph.command(Request.STARTUP) and graph.active()
    capfd.readouterr()
    time.sleep(2.5)  # s of wall time: the stall (the bond checks run on the steady clock)
    deadline = time.monotonic() + 3.0
    while time.monotonic() < deadline:
        graph.executor.spin_once(timeout_sec=0.05)
    assert "CRITICAL FAILURE" not in capfd.readouterr().err
    assert graph.active() and graph.states() == (ACTIVE, ACTIVE)
