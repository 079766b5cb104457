"""``SmaccPublisherClient``: the base of clients that publish on one topic.

SMACC2's ``smacc2::client_bases::SmaccPublisherClient``, whose ``configure<MessageType>(topic)`` is
the constructor here::

    class ClLed(SmaccPublisherClient):
        def __init__(self) -> None:
            super().__init__(ColorRGBA, "/led")

As SMACC2's (``ClRosPublisher()`` then ``configure<Msg>(topic)``), the type and topic may come later:
``client.configure(MsgType, "/topic")`` in the orthogonal's ``on_initialize``, a ``msg_type`` class
attribute, or the node parameter ``<ClientClass>.topic`` (see ``late_config``).

The publisher is created with the machine (``on_initialize``, via ``CpTopicPublisher``), so
subscribers are matched before a state publishes. ``publish`` refuses a message of another type
with a TypeError naming the client, the topic and both types. A subclass that overrides
``on_initialize`` must call ``super().on_initialize()``.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccClient, SmaccError
from smacc_py.ros.client_bases import late_config
from smacc_py.ros.components.checks import DEFAULT_QOS_DEPTH, QosArg, check_created, check_qos
from smacc_py.ros.components.cp_topic_publisher import CpTopicPublisher


class SmaccPublisherClient(ISmaccClient):
    """Publisher of ``msg_type`` on ``topic`` (``qos``: a QoSProfile or a depth); type and topic may be
    None here and given before the machine initializes (see above)."""

    #: The message type when the constructor gets none (SMACC2's ``configure<MessageType>``).
    msg_type: Any = None

    def __init__(self, msg_type: Any = None, topic: str | None = None, qos: QosArg = DEFAULT_QOS_DEPTH
                 ) -> None:
        self.msg_type, self.topic = late_config.check_optional(
            self, type(self).msg_type if msg_type is None else msg_type, topic)
        self.qos = check_qos(late_config.label(self, topic), qos)
        self._publisher: CpTopicPublisher | None = None

    def configure(self, msg_type: Any, topic: str, qos: QosArg | None = None) -> None:
        """SMACC2's ``configure<MessageType>(topic)``: set type and topic (and QoS) before the machine
        initializes, e.g. right after ``create_client`` in the orthogonal's ``on_initialize``."""
        if self._publisher is not None:
            raise SmaccError(f"{late_config.label(self, self.topic)}: configure() after the publisher was "
                             "created")
        self.msg_type, self.topic = late_config.check_optional(self, msg_type, topic)
        if qos is not None:
            self.qos = check_qos(late_config.label(self, topic), qos)

    def on_initialize(self) -> None:
        """Create the publisher component."""
        self.msg_type, self.topic = late_config.resolve(self, self.msg_type, self.topic, "publish on")
        self._publisher = self.create_component(CpTopicPublisher, self.msg_type, self.topic, self.qos)

    @property
    def publisher(self) -> CpTopicPublisher:
        """The component doing the work (SmaccError if ``super().on_initialize()`` was never called)."""
        return check_created(type(self).__name__, self._publisher, "CpTopicPublisher")

    def publish(self, msg: Any) -> None:
        """Publish ``msg`` now (a ``msg_type``; TypeError otherwise)."""
        self.publisher.publish(msg)
