"""A topic client's topic and message type given after construction, as SMACC2's clients take them.

SMACC2 default-constructs ``SmaccSubscriberClient<Msg>()`` and ``ClRosPublisher()``; the topic comes
later (``client->topicName = ...``, ``client->configure<Msg>(topic)`` in the orthogonal's
``onInitialize``), often read from a parameter first. Here a topic client may be built without its
topic, and without its message type when the subclass declares it (``msg_type = Temperature``); it
takes them, in this order:

1. from the constructor, or set afterwards and before the machine initializes its clients:
   ``client.topic = "/x"`` or ``client.configure(MsgType, "/x")`` in the orthogonal's ``on_initialize``;
2. from the node parameter ``<ClientClass>.topic`` (``--ros-args -p ClThermometer.topic:=/x``), read
   when the machine initializes (under the ROS runtime only).

What is still missing then fails at startup with a SmaccError naming the client and these ways.
SMACC2 instead logs an error and skips the subscription, which leaves a machine that never hears its
topic.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient, SmaccError
from smacc_py.ros.components.checks import check_message_type, check_name
from smacc_py.ros.context import ros_context


def topic_parameter(client: ISmaccClient) -> str:
    """The node parameter a client without a topic reads: ``<ClientClass>.topic``."""
    return f"{type(client).__name__}.topic"


def label(client: ISmaccClient, topic: str | None) -> str:
    """How messages name the client: ``ClFoo('/foo')``, or ``ClFoo`` before it knows its topic."""
    name = type(client).__name__
    return name if topic is None else f"{name}({topic!r})"


def check_optional(client: ISmaccClient, msg_type: Any, topic: str | None) -> tuple[Any, str | None]:
    """Check whichever of ``msg_type`` and ``topic`` is given now (None: given later)."""
    owner = label(client, topic)
    checked_type = None if msg_type is None else check_message_type(owner, msg_type)
    checked_topic = None if topic is None else check_name(owner, "topic", topic)
    return checked_type, checked_topic


def resolve(client: ISmaccClient, msg_type: Any, topic: str | None, verb: str) -> tuple[Any, str]:
    """The message type and topic to ``verb`` (subscribe, publish) at initialization; SmaccError naming
    the client and the ways to give them when one is missing."""
    name = type(client).__name__
    if msg_type is None:
        raise SmaccError(
            f"{name}: no message type to {verb}: give it to the constructor ({name}(MsgType, '/topic')), "
            f"declare it on the class (msg_type = MsgType), or call configure(MsgType, '/topic') in the "
            f"orthogonal's on_initialize"
        )
    if topic is None:
        topic = _topic_from_parameter(client)
    if topic is None:
        param = topic_parameter(client)
        raise SmaccError(
            f"{name}: no topic to {verb} (SMACC2 would log 'no topic name set' and skip it): give it to "
            f"the constructor, set client.topic or call configure(MsgType, '/topic') in the orthogonal's "
            f"on_initialize, or set the parameter {param} (--ros-args -p {param}:=/topic)"
        )
    return check_message_type(label(client, topic), msg_type), check_name(label(client, topic), "topic",
                                                                          topic)


def _topic_from_parameter(client: ISmaccClient) -> str | None:
    try:
        node = ros_context(client.sm).node
    except SmaccError:  # run without ROS (smacc_py.testing): no parameters to read
        return None
    param = topic_parameter(client)
    if not node.has_parameter(param):
        node.declare_parameter(param, "")
    value = node.get_parameter(param).value
    return value if isinstance(value, str) and value.strip() else None
