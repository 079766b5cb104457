"""``CpTopicSubscriber``: one topic subscription owned by a client (SMACC2 Jazzy's CpTopicSubscriber).

Every message is posted as ``EvTopicMessage[Client, Orthogonal](msg=...)``, and the first one also,
just before it, as ``EvTopicInitialMessage[Client, Orthogonal](msg=...)``, where Client is the owning
client's type: a transition written against ``ClMySensor`` matches whichever component does the work.
These events have ABSOLUTE lifetime (clients outlive states). Behaviors that want the message itself
connect to ``on_message_received`` / ``on_first_message_received``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core import EvTopicInitialMessage, EvTopicMessage, ISmaccComponent
from smacc_py.ros.components.checks import (
    DEFAULT_QOS_DEPTH,
    QosArg,
    check_message_type,
    check_name,
    check_qos,
)
from smacc_py.ros.components.signal import SmaccSignal
from smacc_py.ros.context import ros_context


class CpTopicSubscriber(ISmaccComponent):
    """Subscribes ``topic`` (``msg_type``, ``qos``: a QoSProfile or a depth) when the machine starts.

    Attributes:
        last_message: the latest message, None before the first.
        message_count: messages received so far.
    """

    def __init__(self, msg_type: Any, topic: str, qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        owner = f"CpTopicSubscriber({topic!r})"
        self.msg_type = check_message_type(owner, msg_type)
        self.topic = check_name(owner, "topic", topic)
        self.qos = check_qos(owner, qos)
        self.last_message: Any = None
        self.message_count = 0
        self.message_received: SmaccSignal[Any] = SmaccSignal(f"{owner}.message_received")
        self.first_message_received: SmaccSignal[Any] = SmaccSignal(f"{owner}.first_message_received")
        self._subscription: Any = None

    def on_initialize(self) -> None:
        node = ros_context(self.sm).node
        self._subscription = node.create_subscription(self.msg_type, self.topic, self.on_message, self.qos)

    def on_message_received(self, listener: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``listener(msg)`` for every message; returns the disconnect function."""
        return self.message_received.connect(listener)

    def on_first_message_received(self, listener: Callable[[Any], None]) -> Callable[[], None]:
        """Call ``listener(msg)`` for the first message only; returns the disconnect function."""
        return self.first_message_received.connect(listener)

    def on_message(self, msg: Any) -> None:
        """Take one message (the subscription's callback, on the executor thread): events, then listeners."""
        first = self.message_count == 0
        self.message_count += 1
        self.last_message = msg
        if first:
            self.post_event(self.owner.own_event(EvTopicInitialMessage)(msg=msg, topic=self.topic))
            self.first_message_received.emit(msg)
        self.post_event(self.owner.own_event(EvTopicMessage)(msg=msg, topic=self.topic))
        self.message_received.emit(msg)
