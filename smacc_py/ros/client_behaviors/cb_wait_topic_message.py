"""``CbWaitTopicMessage``: EvCbSuccess when a message satisfying a predicate arrives on a topic.

SMACC2's ``CbWaitTopicMessage<TMessage>(topic, guardFn)``. The behavior subscribes on entry and
unsubscribes on exit, so only messages published while its state is active count (a latched
message counts when the QoS is transient local on both sides). ``predicate(msg) -> bool`` filters
(None: any message); a predicate that raises ends the wait with EvCbFailure naming the exception.
The success event carries the message as ``msg``. With ``timeout_s`` (machine clock) the wait fails
with EvCbFailure when no accepted message came in time.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import (
    DEFAULT_QOS_DEPTH,
    QosArg,
    check_message_type,
    check_name,
    check_qos,
)
from smacc_py.ros.context import ros_context

_log = logging.getLogger("smacc_py")

Predicate = Callable[[Any], bool]


class CbWaitTopicMessage(CbOutcomeBase):
    """Waits on ``topic`` (``msg_type``, ``qos``) for a message ``predicate`` accepts."""

    def __init__(self, msg_type: Any, topic: str, predicate: Predicate | None = None,
                 timeout_s: float | None = None, qos: QosArg = DEFAULT_QOS_DEPTH) -> None:
        label = f"CbWaitTopicMessage({topic!r})"
        self.msg_type = check_message_type(label, msg_type)
        self.topic = check_name(label, "topic", topic)
        self.qos = check_qos(label, qos)
        if predicate is not None and not callable(predicate):
            raise TypeError(f"{label}: predicate must be callable(msg) -> bool, got {predicate!r}")
        self.predicate = predicate
        self.set_timeout(timeout_s)
        self.seen = 0
        self._subscription: Any = None

    def start(self) -> None:
        node = ros_context(self.sm).node
        self._subscription = node.create_subscription(self.msg_type, self.topic, self.on_message, self.qos)

    def on_message(self, msg: Any) -> None:
        """Take one message (subscription callback): success when the predicate accepts it."""
        if self.finished:
            return
        self.seen += 1
        try:
            accepted = self.predicate is None or bool(self.predicate(msg))
        except Exception as exc:
            _log.exception("CbWaitTopicMessage(%r): the predicate raised", self.topic)
            self.finish(False, reason=f"CbWaitTopicMessage({self.topic!r}): the predicate raised "
                                      f"{type(exc).__name__}: {exc}")
            return
        if accepted:
            self.finish(True, msg=msg)

    def timeout_reason(self) -> str:
        return (f"CbWaitTopicMessage({self.topic!r}): no accepted message within {self.timeout_s:g} s "
                f"({self.seen} received)")

    def stop(self) -> None:
        if self._subscription is not None:
            ros_context(self.sm).node.destroy_subscription(self._subscription)
            self._subscription = None
