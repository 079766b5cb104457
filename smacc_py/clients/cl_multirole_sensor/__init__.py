"""cl_multirole_sensor: ``ClMultiroleSensor`` and ``CbDefaultMultiRoleSensorBehavior`` (SMACC2's
multirole_sensor_client).

``ClMultiroleSensor(msg_type, topic, timeout_s=None)`` is a ``SmaccSubscriberClient`` (a
``CpTopicSubscriber`` and, with ``timeout_s``, a ``CpMessageTimeout``): it posts
``EvTopicMessage``, ``EvTopicInitialMessage`` and ``EvTopicMessageTimeout[ClMultiroleSensor, Or]``
whatever the active state, with ABSOLUTE lifetime. ``CbDefaultMultiRoleSensorBehavior``, active in a
state, re-posts the same news as its own, ``[CbDefaultMultiRoleSensorBehavior, Or]`` (a subclass posts
under its own name), with CURRENT_STATE lifetime, as SMACC2's behavior does; subclass it and override
``on_message_callback(msg)`` to process the messages while the state is active. One sensor client per
orthogonal: subclass ClMultiroleSensor (``class ClLidar(ClMultiroleSensor)``) to tell two sensors
apart in one orthogonal.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from smacc_py.core import EvTopicInitialMessage, EvTopicMessage, SmaccClientBehavior, SmaccLookupError
from smacc_py.ros.client_bases import EvTopicMessageTimeout, SmaccSubscriberClient
from smacc_py.ros.components.checks import DEFAULT_QOS_DEPTH, QosArg


class ClMultiroleSensor(SmaccSubscriberClient):
    """A sensor topic (``msg_type`` on ``topic``) with an optional silence watchdog ``timeout_s`` (s); type
    and topic may come later, as for every SmaccSubscriberClient."""

    def __init__(self, msg_type: Any = None, topic: str | None = None, timeout_s: float | None = None,
                 qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        super().__init__(msg_type, topic, qos=qos, timeout_s=timeout_s)


class CbDefaultMultiRoleSensorBehavior(SmaccClientBehavior):
    """Re-posts the sensor's messages and timeouts as its own events while its state is active."""

    def on_entry(self) -> None:
        sensor = self.orthogonal.get_client(ClMultiroleSensor)
        if sensor is None:
            raise SmaccLookupError(f"{type(self).__name__}: no ClMultiroleSensor on "
                                   f"{type(self.orthogonal).__name__}")
        self.sensor = sensor
        self._disconnect: list[Callable[[], None]] = [
            sensor.on_first_message_received(self._on_first_message),
            sensor.on_message_received(self._on_message),
        ]
        if sensor.watchdog is not None:
            self._disconnect.append(sensor.on_message_timeout(self._on_timeout))

    def _on_first_message(self, msg: Any) -> None:
        self.post_event(self.own_event(EvTopicInitialMessage)(msg=msg, topic=self.sensor.topic))

    def _on_message(self, msg: Any) -> None:
        self.post_event(self.own_event(EvTopicMessage)(msg=msg, topic=self.sensor.topic))
        self.on_message_callback(msg)

    def _on_timeout(self, silence_s: float) -> None:
        self.post_event(self.own_event(EvTopicMessageTimeout)(topic=self.sensor.topic, silence_s=silence_s))

    def on_message_callback(self, msg: Any) -> None:
        """Hook for subclasses: each message while the state is active (executor thread; be quick)."""

    def on_exit(self) -> None:
        for disconnect in self._disconnect:
            disconnect()


__all__ = ["CbDefaultMultiRoleSensorBehavior", "ClMultiroleSensor", "EvTopicMessageTimeout"]
