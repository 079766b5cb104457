"""``SmaccPublisherClient``: the base of clients that publish on one topic.

SMACC2's ``smacc2::client_bases::SmaccPublisherClient``, whose ``configure<MessageType>(topic)`` is
the constructor here::

    class ClLed(SmaccPublisherClient):
        def __init__(self) -> None:
            super().__init__(ColorRGBA, "/led")

The publisher is created with the machine (``on_initialize``, via ``CpTopicPublisher``), so
subscribers are matched before a state publishes. ``publish`` refuses a message of another type
with a TypeError naming the client, the topic and both types. A subclass that overrides
``on_initialize`` must call ``super().on_initialize()``.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient
from smacc_py.ros.components.checks import (
    DEFAULT_QOS_DEPTH,
    QosArg,
    check_created,
    check_message_type,
    check_name,
    check_qos,
)
from smacc_py.ros.components.cp_topic_publisher import CpTopicPublisher


class SmaccPublisherClient(ISmaccClient):
    """Publisher of ``msg_type`` on ``topic`` (``qos``: a QoSProfile or a depth)."""

    def __init__(self, msg_type: Any, topic: str, qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        label = f"{type(self).__name__}({topic!r})"
        self.msg_type = check_message_type(label, msg_type)
        self.topic = check_name(label, "topic", topic)
        self.qos = check_qos(label, qos)
        self._publisher: CpTopicPublisher | None = None

    def on_initialize(self) -> None:
        """Create the publisher component."""
        self._publisher = self.create_component(CpTopicPublisher, self.msg_type, self.topic, self.qos)

    @property
    def publisher(self) -> CpTopicPublisher:
        """The component doing the work (SmaccError if ``super().on_initialize()`` was never called)."""
        return check_created(type(self).__name__, self._publisher, "CpTopicPublisher")

    def publish(self, msg: Any) -> None:
        """Publish ``msg`` now (a ``msg_type``; TypeError otherwise)."""
        self.publisher.publish(msg)
