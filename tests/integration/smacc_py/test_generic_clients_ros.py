"""The generic clients over real rclpy: machines on SmaccRuntime against a peer node (topics, a
service, an action server, a caller of our service), and the README's client guide end to end."""

from __future__ import annotations

import contextlib
import functools
import sys
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from nav2_msgs.action import Wait
from rclpy.action import ActionServer
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from sensor_msgs.msg import Temperature
from std_msgs.msg import String
from std_srvs.srv import Trigger

from navsuite_testing.ros import wait_until
from smacc_py.clients import (
    CbCallService,
    CbPublishOnce,
    CbRosLaunch,
    CbSequence,
    CbWaitNode,
    CbWaitTopicMessage,
    ClMultiroleSensor,
    ClRosPublisher,
    EvServiceRequestReceived,
    EvTopicMessageTimeout,
    SmaccServiceServerClient,
)
from smacc_py.core import (
    EvCbFailure,
    EvCbSuccess,
    EvSequenceFinished,
    Orthogonal,
    SmaccEvent,
    SmaccObserver,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.examples.writing_clients import SmClientGuide
from smacc_py.ros.runtime import SmaccRuntime

pytestmark = pytest.mark.ros

DEADLINE_S = 60.0  # wall s: a failure guard only; the runs take a few seconds


class Peer:
    """The other side of the graph, spun in its own thread: a `wait` action server that succeeds at
    once, /temperature and /generic_chatter publishers (10 Hz wall), the /generic_trigger service, and
    a caller of our /generic_start that calls every 0.3 s once it heard "heard" on /generic_out."""

    def __init__(self, context: Any) -> None:
        self.node = Node("generic_peer", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self.ticks = 0
        self.heard = False
        self.trigger_calls = 0
        self._action = ActionServer(self.node, Wait, "wait", self._execute)
        self._temperature = self.node.create_publisher(Temperature, "/temperature", 10)
        self._chatter = self.node.create_publisher(String, "/generic_chatter", 10)
        self._trigger = self.node.create_service(Trigger, "/generic_trigger", self._on_trigger)
        self._start_client = self.node.create_client(Trigger, "/generic_start")
        self._out = self.node.create_subscription(String, "/generic_out", self._on_out, 10)
        self._timers = [self.node.create_timer(0.1, self._tick),
                        self.node.create_timer(0.3, self._call_start)]
        self._stopping = False
        self._thread = threading.Thread(target=self._spin, name="generic_peer", daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        with contextlib.suppress(Exception):  # the context may shut down under us at teardown
            while not self._stopping and self.executor.context.ok():
                self.executor.spin_once(timeout_sec=0.1)

    def _execute(self, goal_handle: Any) -> Wait.Result:
        goal_handle.succeed()
        return Wait.Result()

    def _tick(self) -> None:
        self.ticks += 1
        self._temperature.publish(Temperature(temperature=20.0 + self.ticks))
        self._chatter.publish(String(data=f"tick {self.ticks}"))

    def _on_trigger(self, request: Any, response: Any) -> Any:
        self.trigger_calls += 1
        response.success, response.message = True, "triggered"
        return response

    def _on_out(self, msg: String) -> None:
        self.heard = self.heard or msg.data == "heard"

    def _call_start(self) -> None:
        if self.heard and self._start_client.service_is_ready():
            self._start_client.call_async(Trigger.Request())

    def stop(self) -> None:
        self._stopping = True
        self._thread.join(2.0)
        self.executor.shutdown()
        self._action.destroy()
        self.node.destroy_node()


class Recorder(SmaccObserver):
    def __init__(self) -> None:
        self.posted: list[type] = []

    def on_event_posted(self, sm: Any, event: SmaccEvent) -> None:
        self.posted.append(type(event))


@pytest.fixture
def run(ros_context: Any) -> Iterator[Any]:
    """``run(SmType)`` starts the peer and the machine (wall clock); both are torn down afterwards."""
    made: list[Any] = []

    def start(sm_type: type[SmaccStateMachineBase]) -> tuple[SmaccRuntime, Peer, Recorder]:
        peer = Peer(ros_context)
        made.append(peer)
        runtime = SmaccRuntime(sm_type, context=ros_context)
        made.append(runtime)
        recorder = Recorder()
        runtime.sm.add_observer(recorder)
        runtime.spin_in_background()
        runtime.start()
        return runtime, peer, recorder

    try:
        yield start
    finally:
        for item in reversed(made):
            with contextlib.suppress(Exception):
                item.shutdown() if isinstance(item, SmaccRuntime) else item.stop()


def _ended(runtime: SmaccRuntime) -> bool:
    names = runtime.sm.current_state_names()
    return bool(names) and names[-1] in ("StDone", "StFailed")


def _path(runtime: SmaccRuntime) -> list[str]:
    return [record.key()[1] for record in list(runtime.sm.transition_log)]


# ----------------------------------------------------------------------------- a machine of generic pieces
class ClStart(SmaccServiceServerClient):
    def __init__(self) -> None:
        super().__init__(Trigger, "/generic_start")


class OrTools(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClRosPublisher, String, "/generic_out")


class OrServer(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClStart)


class OrSensor(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClMultiroleSensor, String, "/generic_silent", 0.5)


class SmGeneric(SmaccStateMachineBase):
    initial_state = "StWaitPeer"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrTools)
        self.create_orthogonal(OrServer)
        self.create_orthogonal(OrSensor)


def _is_tick(msg: String) -> bool:
    return msg.data.startswith("tick")


class StWaitPeer(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvCbSuccess[CbWaitNode, OrTools], "StCall"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTools, CbWaitNode, "generic_peer", DEADLINE_S)


class StCall(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvCbSuccess[CbCallService, OrTools], "StListen"),
                 Transition(EvCbFailure[CbCallService, OrTools], "StFailed"))

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTools, CbCallService, Trigger, "/generic_trigger", None, DEADLINE_S,
                                 lambda response: response.success)


class StListen(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvCbSuccess[CbSequence, OrTools], "StServe"),
                 Transition(EvCbFailure[CbSequence, OrTools], "StFailed"))

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTools, CbSequence, [
            functools.partial(CbWaitTopicMessage, String, "/generic_chatter", _is_tick, DEADLINE_S),
            functools.partial(CbPublishOnce, String(data="heard")),
        ])


class StServe(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvServiceRequestReceived[ClStart, OrServer], "StLaunch"),)


class StLaunch(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvCbFailure[CbRosLaunch, OrTools], "StMissingService"),
                 Transition(EvCbSuccess[CbRosLaunch, OrTools], "StFailed"))

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTools, CbRosLaunch, [sys.executable, "-c", "raise SystemExit(2)"])


class StMissingService(SmaccState, parent=SmGeneric):
    reactions = (Transition(EvCbFailure[CbCallService, OrTools], "StDone"),
                 Transition(EvCbSuccess[CbCallService, OrTools], "StFailed"))

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTools, CbCallService, Trigger, "/nobody_serves_this", None, 1.0)


class StDone(SmaccState, parent=SmGeneric):
    pass


class StFailed(SmaccState, parent=SmGeneric):
    pass


def test_generic_behaviors_and_clients_drive_a_machine_over_real_topics_services_and_processes(
        run: Any) -> None:
    runtime, peer, recorder = run(SmGeneric)
    wait_until(lambda: _ended(runtime), DEADLINE_S, "the machine to end")
    assert _path(runtime) == ["StCall", "StListen", "StServe", "StLaunch", "StMissingService", "StDone"]
    assert peer.trigger_calls == 1 and peer.heard
    assert EvSequenceFinished[StListen] in recorder.posted
    assert EvTopicMessageTimeout[ClMultiroleSensor, OrSensor] in recorder.posted, "the silent topic timed out"


def test_the_readme_client_guide_runs_against_a_real_action_server_and_topic(run: Any) -> None:
    runtime, _peer, _recorder = run(SmClientGuide)
    wait_until(lambda: _ended(runtime), DEADLINE_S, "the guide to end")
    assert _path(runtime) == ["StWaitAction", "StFirstReading", "StWaitHot", "StDone"]
