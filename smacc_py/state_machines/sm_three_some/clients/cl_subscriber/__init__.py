"""``ClSubscriber``: a multirole sensor of std_msgs/UInt16 on /keyboard_unicode, and its behaviors.

Upstream's current ClSubscriber is a ``cl_generic_sensor::ClGenericSensor<std_msgs::msg::UInt16>`` (the
multirole sensor client under its newer name) whose topic is the keyboard's, "for testing": so every
key press is also a sensor message. Upstream leaves its watchdog off; so does this port.
"""

from __future__ import annotations

from std_msgs.msg import UInt16

from smacc_py.clients import ClMultiroleSensor
from smacc_py.clients.cl_keyboard import KEYBOARD_TOPIC
from smacc_py.state_machines.sm_three_some.clients.cl_subscriber.client_behaviors import (
    CbDefaultSubscriberBehavior,
    CbWatchdogSubscriberBehavior,
)


class ClSubscriber(ClMultiroleSensor):
    """UInt16 messages of /keyboard_unicode, posted as EvTopicMessage[ClSubscriber, Or]."""

    msg_type = UInt16

    def __init__(self) -> None:
        super().__init__(UInt16, KEYBOARD_TOPIC)


__all__ = ["CbDefaultSubscriberBehavior", "CbWatchdogSubscriberBehavior", "ClSubscriber"]
