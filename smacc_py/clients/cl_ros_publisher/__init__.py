"""cl_ros_publisher: ``ClRosPublisher`` and its behaviors (SMACC2's ros_publisher_client).

``ClRosPublisher(msg_type, topic)`` is a ``SmaccPublisherClient``; as SMACC2's, it may also be created
bare and configured in the orthogonal (``create_client(ClRosPublisher).configure(String, "/out")``, the
Python of ``createClient<ClRosPublisher>()->configure<String>("/out")``) or take its topic from the
parameter ``ClRosPublisher.topic``. Pick a behavior per state:

* ``CbPublishOnce(msg)`` publishes ``msg`` on entry, then posts ``EvCbSuccess[CbPublishOnce, Or]`` (an
  addition to SMACC2's, so that a state can move on once it has spoken);
* ``CbDefaultPublishLoop(msg, period_s=None)`` republishes ``msg`` on every runtime poll, or every
  ``period_s`` s of machine clock (sim time under ``use_sim_time``), while its state is active;
* ``CbMuteBehavior`` publishes nothing: a state that wants its orthogonal quiet says so explicitly
  (SMACC2 spells it ``CbMutedBehavior``; both names work).

The message may also come later, as SMACC2's ``setMessage``: ``set_message(msg)`` (or ``setMessage``)
before the behavior's ``on_entry``, e.g. from the state's ``runtime_configure``. A publish loop without a
message publishes nothing, as SMACC2's; a CbPublishOnce without one fails on entry with a message.
A message that is not a ROS message fails at construction (or in ``set_message``) with a TypeError
naming the behavior; on entry it is checked against the client's type.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior, SmaccError
from smacc_py.ros.client_bases import SmaccPublisherClient
from smacc_py.ros.components.checks import DEFAULT_QOS_DEPTH, QosArg, check_duration, check_instance


class ClRosPublisher(SmaccPublisherClient):
    """Publisher of ``msg_type`` on ``topic`` (SMACC2's ``cl_ros_publisher::ClRosPublisher``); both may be
    given later with ``configure`` or the ``ClRosPublisher.topic`` parameter."""

    def __init__(self, msg_type: Any = None, topic: str | None = None, qos: QosArg = DEFAULT_QOS_DEPTH
                 ) -> None:
        super().__init__(msg_type, topic, qos)


class _CbPublishBase(SmaccClientBehavior):
    def __init__(self, msg: Any = None) -> None:
        self.msg: Any = None
        if msg is not None:
            self.set_message(msg)
        self.published = 0

    def set_message(self, msg: Any) -> None:
        """The message to publish from now on (SMACC2's ``setMessage``)."""
        if not hasattr(type(msg), "get_fields_and_field_types"):
            raise TypeError(f"{type(self).__name__}: expected a ROS message instance, got {msg!r}")
        self.msg = msg

    setMessage = set_message  # SMACC2's spelling

    def on_entry(self) -> None:
        self.client = self.requires_client(ClRosPublisher)
        if self.msg is not None:
            check_instance(f"{type(self).__name__} on {self.client.topic!r}", "the message", self.msg,
                           self.client.msg_type)

    def publish(self) -> None:
        """Publish the message through the client (nothing while no message is set)."""
        if self.msg is None:
            return
        self.client.publish(self.msg)
        self.published += 1


class CbPublishOnce(_CbPublishBase):
    """Publishes ``msg`` once on entry, then posts EvCbSuccess."""

    def on_entry(self) -> None:
        super().on_entry()
        if self.msg is None:
            raise SmaccError(f"{type(self).__name__}: no message to publish; give one to the constructor or "
                             "call set_message() before entry (e.g. in the state's runtime_configure)")
        self.publish()
        self.post_success_event()


class CbDefaultPublishLoop(_CbPublishBase, ISmaccUpdatable):
    """Publishes ``msg`` on entry and then on every poll, or every ``period_s`` s (machine clock)."""

    def __init__(self, msg: Any = None, period_s: float | None = None) -> None:
        super().__init__(msg)
        if period_s is not None:
            self.set_update_period(check_duration("CbDefaultPublishLoop", "period_s", period_s))

    def on_entry(self) -> None:
        super().on_entry()
        self.publish()
        self._last_update_s = self.sm.now()  # the entry's message counts as this period's

    def update(self) -> None:
        """Publish again (runtime polling, machine thread)."""
        self.publish()


class CbMuteBehavior(SmaccClientBehavior):
    """Publishes nothing while its state is active."""


CbMutedBehavior = CbMuteBehavior

__all__ = ["CbDefaultPublishLoop", "CbMuteBehavior", "CbMutedBehavior", "CbPublishOnce", "ClRosPublisher"]
