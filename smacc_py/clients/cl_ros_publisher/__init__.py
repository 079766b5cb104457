"""cl_ros_publisher: ``ClRosPublisher`` and its behaviors (SMACC2's ros_publisher_client).

``ClRosPublisher(msg_type, topic)`` is a ``SmaccPublisherClient``; configure it on an orthogonal and
pick a behavior per state:

* ``CbPublishOnce(msg)`` publishes ``msg`` on entry, then posts ``EvCbSuccess[CbPublishOnce, Or]`` (an
  addition to SMACC2's, so that a state can move on once it has spoken);
* ``CbDefaultPublishLoop(msg, period_s=None)`` republishes ``msg`` on every runtime poll, or every
  ``period_s`` s of machine clock (sim time under ``use_sim_time``), while its state is active;
* ``CbMuteBehavior`` publishes nothing: a state that wants its orthogonal quiet says so explicitly
  (SMACC2 spells it ``CbMutedBehavior``; both names work).

A message of the wrong type fails at construction with a TypeError naming the behavior, the topic's
type and the message's; the check runs again on entry against the client's type.
"""

from __future__ import annotations

from typing import Any

from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior
from smacc_py.ros.client_bases import SmaccPublisherClient
from smacc_py.ros.components.checks import DEFAULT_QOS_DEPTH, QosArg, check_duration, check_instance


class ClRosPublisher(SmaccPublisherClient):
    """Publisher of ``msg_type`` on ``topic`` (SMACC2's ``cl_ros_publisher::ClRosPublisher``)."""

    def __init__(self, msg_type: Any, topic: str, qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        super().__init__(msg_type, topic, qos)


class _CbPublishBase(SmaccClientBehavior):
    def __init__(self, msg: Any) -> None:
        if not hasattr(type(msg), "get_fields_and_field_types"):
            raise TypeError(f"{type(self).__name__}: expected a ROS message instance, got {msg!r}")
        self.msg = msg
        self.published = 0

    def on_entry(self) -> None:
        self.client = self.requires_client(ClRosPublisher)
        check_instance(f"{type(self).__name__} on {self.client.topic!r}", "the message", self.msg,
                       self.client.msg_type)

    def publish(self) -> None:
        """Publish the message through the client."""
        self.client.publish(self.msg)
        self.published += 1


class CbPublishOnce(_CbPublishBase):
    """Publishes ``msg`` once on entry, then posts EvCbSuccess."""

    def on_entry(self) -> None:
        super().on_entry()
        self.publish()
        self.post_success_event()


class CbDefaultPublishLoop(_CbPublishBase, ISmaccUpdatable):
    """Publishes ``msg`` on entry and then on every poll, or every ``period_s`` s (machine clock)."""

    def __init__(self, msg: Any, period_s: float | None = None) -> None:
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
