"""Topic clients take their topic (and message) later, as SMACC2's: ``ClRosPublisher()`` then
``configure(Msg, topic)``, a subscriber whose ``topic`` is set in the orthogonal or read from the node
parameter ``<ClientClass>.topic``, and publish behaviors whose message comes from ``set_message``. What
is still missing at startup fails naming the client and the ways to give it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import pytest
from std_msgs.msg import Int32, String

from smacc_py.clients import CbDefaultPublishLoop, CbPublishOnce, ClRosPublisher, SmaccSubscriberClient
from smacc_py.core import (
    EvCbSuccess,
    EvTopicMessage,
    Orthogonal,
    SmaccError,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.ros.context import RosContext, attach_ros_context
from smacc_py.testing import MachineHarness


class ClCounter(SmaccSubscriberClient):
    """SMACC2's ``SmaccSubscriberClient<Int32>()``: the type is the class's, the topic comes later."""

    msg_type = Int32


class OrIo(Orthogonal):
    topic: str | None = "/count"

    def on_initialize(self) -> None:
        self.create_client(ClRosPublisher).configure(String, "/said")  # createClient<>()->configure<>()
        counter = self.create_client(ClCounter)
        if self.topic is not None:
            counter.topic = self.topic  # SMACC2: client->topicName = ...


class StListen(SmaccState, parent="SmLate"):
    reactions = (Transition(EvTopicMessage[ClCounter, OrIo], "StSpeak"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrIo, CbDefaultPublishLoop)  # no message yet: publishes nothing


class StSpeak(SmaccState, parent="SmLate"):
    reactions = (Transition(EvCbSuccess[CbPublishOnce, OrIo], "StDone"),)

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrIo, CbPublishOnce)

    def runtime_configure(self) -> None:  # SMACC2: the behavior's setMessage in runtimeConfigure
        self.get_client_behavior(OrIo, CbPublishOnce).setMessage(String(data="heard"))


class StDone(SmaccState, parent="SmLate"):
    pass


class SmLate(SmaccStateMachineBase):
    initial_state = StListen

    def on_initialize(self) -> None:
        self.create_orthogonal(OrIo)


def test_topics_set_in_the_orthogonal_and_messages_set_before_entry_work() -> None:
    with MachineHarness(SmLate) as harness:
        harness.advance(1.0)
        assert harness.published("/said") == []  # the loop has no message: nothing, as SMACC2's
        assert harness.deliver("/count", Int32(data=3)) == 1
        assert harness.sm.current_state_names() == ["StDone"]
        assert harness.published("/said") == [String(data="heard")]
        assert harness.sm.requires_client(ClCounter).last_message == Int32(data=3)


@dataclass
class _Parameter:
    value: Any


class ParameterNode:
    """The parameter calls of an rclpy node, with ``--ros-args -p`` overrides."""

    def __init__(self, overrides: dict[str, Any]) -> None:
        self.overrides = overrides
        self.declared: dict[str, _Parameter] = {}

    def has_parameter(self, name: str) -> bool:
        return name in self.declared

    def declare_parameter(self, name: str, default: Any) -> _Parameter:
        self.declared[name] = _Parameter(self.overrides.get(name, default))
        return self.declared[name]

    def get_parameter(self, name: str) -> _Parameter:
        return self.declared[name]


def _without_topic(harness: MachineHarness[Any], overrides: dict[str, Any] | None) -> None:
    OrIo.topic = None
    try:
        if overrides is not None:
            attach_ros_context(harness.sm, RosContext(ParameterNode(overrides)))  # type: ignore[arg-type]
        harness.start()
    finally:
        OrIo.topic = "/count"


def test_a_subscriber_without_a_topic_reads_the_client_parameter() -> None:
    harness = MachineHarness(SmLate)
    _without_topic(harness, {"ClCounter.topic": "/from_param"})
    with harness:
        assert harness.sm.requires_client(ClCounter).topic == "/from_param"
        assert harness.deliver("/from_param", Int32(data=1)) == 1
        assert harness.sm.current_state_names() == ["StDone"]


@pytest.mark.parametrize("overrides", [None, {}])
def test_a_subscriber_without_any_topic_fails_at_startup_saying_how_to_give_one(
        overrides: dict[str, Any] | None) -> None:
    with pytest.raises(SmaccError) as caught:
        _without_topic(MachineHarness(SmLate), overrides)
    message = str(caught.value)
    assert message.startswith("ClCounter: no topic to subscribe to (SMACC2 would log 'no topic name set'")
    assert "set client.topic or call configure(MsgType, '/topic')" in message
    assert "the parameter ClCounter.topic (--ros-args -p ClCounter.topic:=/topic)" in message


def test_a_client_without_a_message_type_says_how_to_give_one() -> None:
    class OrBare(Orthogonal):
        def on_initialize(self) -> None:
            self.create_client(ClRosPublisher, topic="/x")

    class StBare(SmaccState, parent="SmBare"):
        pass

    class SmBare(SmaccStateMachineBase):
        initial_state = StBare

        def on_initialize(self) -> None:
            self.create_orthogonal(OrBare)

    with pytest.raises(SmaccError, match=r"ClRosPublisher: no message type to publish on: give it to the "
                                         r"constructor .* declare it on the class \(msg_type = MsgType\)"):
        MachineHarness(SmBare).start()


def test_publish_behaviors_check_a_message_given_later() -> None:
    with pytest.raises(TypeError, match=r"CbDefaultPublishLoop: expected a ROS message instance, got 'hi'"):
        CbDefaultPublishLoop().set_message("hi")
    loop = CbDefaultPublishLoop()
    loop.setMessage(String(data="ok"))
    assert loop.msg == String(data="ok")
