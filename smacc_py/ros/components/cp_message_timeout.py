"""``CpMessageTimeout``: a watchdog posting ``EvTopicMessageTimeout`` when a topic goes silent.

Like SMACC2's multirole_sensor_client CpMessageTimeout: it watches its client's CpTopicSubscriber and,
after ``timeout_s`` seconds of the machine clock (sim time under ``use_sim_time``) without a message,
posts ``EvTopicMessageTimeout[Client, Orthogonal](topic=..., silence_s=...)``, then again after every
further ``timeout_s`` of silence, as SMACC2's re-armed timer does. Silence is measured from the first
poll after the machine started, not from construction: under sim time the clock reads 0 until the
first /clock message. The check runs in the runtime's ISmaccUpdatable polling, so the event comes at
most one poll (1 / signal_detector_loop_freq s) after the deadline.
"""

from __future__ import annotations

from smacc_py.core import ISmaccComponent, ISmaccUpdatable, SmaccEvent
from smacc_py.ros.components.checks import check_duration
from smacc_py.ros.components.cp_topic_subscriber import CpTopicSubscriber
from smacc_py.ros.components.signal import SmaccSignal


class EvTopicMessageTimeout(SmaccEvent):
    """No message arrived on a watched topic for the timeout; parameters are (source, orthogonal).

    Payload: ``topic`` and ``silence_s`` (s of machine clock since the last message or the start).
    """


class CpMessageTimeout(ISmaccComponent, ISmaccUpdatable):
    """Watchdog on the CpTopicSubscriber of the same client (or, failing that, of any client)."""

    def __init__(self, timeout_s: float) -> None:
        self.timeout_s = check_duration("CpMessageTimeout", "timeout_s", timeout_s)
        self.timed_out: SmaccSignal[float] = SmaccSignal("CpMessageTimeout.timed_out")
        self.timeouts = 0
        self._since_s: float | None = None

    def on_initialize(self) -> None:
        self.subscriber = self.requires_component(CpTopicSubscriber)
        self.subscriber.on_message_received(self._on_message)

    def _on_message(self, _msg: object) -> None:
        self._since_s = self.sm.now()

    def update(self) -> None:
        """Post the timeout event once ``timeout_s`` passed since the last message (or the last event)."""
        now = self.sm.now()
        if self._since_s is None:
            self._since_s = now
            return
        silence = now - self._since_s
        if silence >= self.timeout_s:
            self._since_s = now
            self.timeouts += 1
            self.post_event(self.owner.own_event(EvTopicMessageTimeout)(topic=self.subscriber.topic,
                                                                        silence_s=silence))
            self.timed_out.emit(silence)
