"""``CpTopicPublisher``: one topic publisher owned by a client (SMACC2 Jazzy's CpTopicPublisher).

The publisher is created when the machine starts (``on_initialize``), not when a behavior first
publishes, so DDS has discovered the subscribers by the time a state wants to say something.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccComponent, SmaccError
from smacc_py.ros.components.checks import (
    DEFAULT_QOS_DEPTH,
    QosArg,
    check_instance,
    check_message_type,
    check_name,
    check_qos,
)
from smacc_py.ros.context import ros_context


class CpTopicPublisher(ISmaccComponent):
    """Publishes ``msg_type`` messages on ``topic`` (``qos``: a QoSProfile or a depth)."""

    def __init__(self, msg_type: Any, topic: str, qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        self.label = f"CpTopicPublisher({topic!r})"
        self.msg_type = check_message_type(self.label, msg_type)
        self.topic = check_name(self.label, "topic", topic)
        self.qos = check_qos(self.label, qos)
        self._publisher: Any = None

    def on_initialize(self) -> None:
        node = ros_context(self.sm).node
        self._publisher = node.create_publisher(self.msg_type, self.topic, self.qos)

    def publish(self, msg: Any) -> None:
        """Publish ``msg``; TypeError when it is not a ``msg_type``, SmaccError before the machine started."""
        check_instance(self.label, "the message", msg, self.msg_type)
        if self._publisher is None:
            raise SmaccError(f"{self.label}: publish() before the machine was initialized")
        self._publisher.publish(msg)
