"""``SmaccSubscriberClient``: the base of clients that listen to one topic.

SMACC2's ``smacc2::client_bases::SmaccSubscriberClient<MessageType>``: every message is posted as
``EvTopicMessage[YourClient, Or](msg=...)`` and the first one also as
``EvTopicInitialMessage[YourClient, Or](msg=...)``. Beyond SMACC2's base, ``timeout_s`` adds the
multirole sensor's watchdog: ``EvTopicMessageTimeout[YourClient, Or]`` after ``timeout_s`` seconds of
machine clock without a message, and again after each further ``timeout_s`` of silence::

    class ClTemperature(SmaccSubscriberClient):
        def __init__(self) -> None:
            super().__init__(Temperature, "/temperature", timeout_s=2.0)

As SMACC2's ``SmaccSubscriberClient<Msg>()``, the topic may come later: set ``client.topic`` (or call
``configure``) in the orthogonal's ``on_initialize``, or set the node parameter ``<ClientClass>.topic``;
a subclass may declare its message type as a class attribute (``msg_type = Temperature``) and take no
arguments at all (see ``late_config``).

The work is done by components created in ``on_initialize`` (``CpTopicSubscriber`` and, with a
timeout, ``CpMessageTimeout``); a subclass that overrides ``on_initialize`` must call
``super().on_initialize()``. SMACC2 subscribes with the sensor-data QoS; the default here is rclpy's
(reliable, depth 10), which also hears reliable publishers' latched messages. Pass
``rclpy.qos.qos_profile_sensor_data`` for best-effort sensors.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core import ISmaccClient, SmaccError
from smacc_py.ros.client_bases import late_config
from smacc_py.ros.components.checks import DEFAULT_QOS_DEPTH, QosArg, check_created, check_qos, check_timeout
from smacc_py.ros.components.cp_message_timeout import CpMessageTimeout, EvTopicMessageTimeout
from smacc_py.ros.components.cp_topic_subscriber import CpTopicSubscriber

__all__ = ["EvTopicMessageTimeout", "SmaccSubscriberClient"]


class SmaccSubscriberClient(ISmaccClient):
    """Subscriber of ``topic`` (``msg_type``, ``qos``); ``timeout_s`` (s, None: no watchdog).

    ``msg_type`` and ``topic`` may be None here and given before the machine initializes (see above).
    """

    #: The message type when the constructor gets none (SMACC2's template argument).
    msg_type: Any = None

    def __init__(self, msg_type: Any = None, topic: str | None = None, qos: QosArg = DEFAULT_QOS_DEPTH,
                 timeout_s: float | None = None) -> None:
        self.msg_type, self.topic = late_config.check_optional(
            self, type(self).msg_type if msg_type is None else msg_type, topic)
        owner = late_config.label(self, topic)
        self.qos = check_qos(owner, qos)
        self.timeout_s = check_timeout(owner, "timeout_s", timeout_s)
        self._subscriber: CpTopicSubscriber | None = None
        self.watchdog: CpMessageTimeout | None = None

    def configure(self, msg_type: Any, topic: str) -> None:
        """Set the message type and topic before the machine initializes (SMACC2's ``topicName``)."""
        if self._subscriber is not None:
            raise SmaccError(f"{late_config.label(self, self.topic)}: configure() after the subscription "
                             "was made")
        self.msg_type, self.topic = late_config.check_optional(self, msg_type, topic)

    def on_initialize(self) -> None:
        """Create the subscriber component and, with ``timeout_s``, the watchdog."""
        self.msg_type, self.topic = late_config.resolve(self, self.msg_type, self.topic, "subscribe to")
        self._subscriber = self.create_component(CpTopicSubscriber, self.msg_type, self.topic, self.qos)
        if self.timeout_s is not None:
            self.watchdog = self.create_component(CpMessageTimeout, self.timeout_s)

    @property
    def subscriber(self) -> CpTopicSubscriber:
        """The component doing the work (SmaccError if ``super().on_initialize()`` was never called)."""
        return check_created(type(self).__name__, self._subscriber, "CpTopicSubscriber")

    @property
    def last_message(self) -> Any:
        """The latest message, None before the first."""
        return self.subscriber.last_message

    def on_message_received(self, listener: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``listener(msg)`` for every message (executor thread); returns the disconnect function."""
        return self.subscriber.on_message_received(listener)

    def on_first_message_received(self, listener: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``listener(msg)`` for the first message; returns the disconnect function."""
        return self.subscriber.on_first_message_received(listener)

    def on_message_timeout(self, listener: Callable[[float], None]) -> Callable[[], None]:
        """Call ``listener(silence_s)`` on each timeout; SmaccError when the client has no ``timeout_s``."""
        if self.watchdog is None:
            raise SmaccError(f"{type(self).__name__}({self.topic!r}) has no message timeout; give timeout_s")
        return self.watchdog.timed_out.connect(listener)
