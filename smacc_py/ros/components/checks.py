"""Checks of the arguments users give generic clients, components and behaviors.

Why a module of its own: a wrong argument (an empty topic name, a message class where a service class
belongs, a negative timeout) must fail when the object is built, with a message that names the
object and the value, not later inside rclpy with a message about C type support. Every check
raises ``ValueError`` for a bad value and ``TypeError`` for a bad type.
"""

from __future__ import annotations

import math
from typing import Any, TypeVar

from rclpy.qos import QoSProfile

from smacc_py.core import SmaccError

#: Depth of the default QoS (reliable, volatile, keep last), as rclpy's ``qos_profile=10``.
DEFAULT_QOS_DEPTH = 10

QosArg = QoSProfile | int
T = TypeVar("T")


def check_name(owner: str, kind: str, name: object) -> str:
    """``name`` as a ROS name for ``kind`` (topic, service, action, node); ValueError when empty."""
    if not isinstance(name, str):
        raise TypeError(f"{owner}: the {kind} name must be a str, got {name!r}")
    if not name.strip():
        raise ValueError(f"{owner}: the {kind} name is empty ({name!r})")
    return name


def _type_label(value: object) -> str:
    return value.__name__ if isinstance(value, type) else f"{value!r} (a {type(value).__name__})"


def check_message_type(owner: str, msg_type: object) -> Any:
    """``msg_type`` if it is a ROS message class (std_msgs.msg.String, not an instance or a service)."""
    if not (isinstance(msg_type, type) and hasattr(msg_type, "get_fields_and_field_types")):
        raise TypeError(f"{owner}: expected a ROS message class such as std_msgs.msg.String, got "
                        f"{_type_label(msg_type)}")
    return msg_type


def check_service_type(owner: str, srv_type: object) -> Any:
    """``srv_type`` if it is a ROS service class (it has ``Request`` and ``Response``)."""
    if not (isinstance(srv_type, type) and hasattr(srv_type, "Request") and hasattr(srv_type, "Response")
            and not hasattr(srv_type, "Goal")):
        raise TypeError(f"{owner}: expected a ROS service class such as std_srvs.srv.Trigger, got "
                        f"{_type_label(srv_type)}")
    return srv_type


def check_action_type(owner: str, action_type: object) -> Any:
    """``action_type`` if it is a ROS action class (it has ``Goal``, ``Result`` and ``Feedback``)."""
    if not (isinstance(action_type, type)
            and all(hasattr(action_type, part) for part in ("Goal", "Result", "Feedback"))):
        raise TypeError(f"{owner}: expected a ROS action class such as nav2_msgs.action.Wait, got "
                        f"{_type_label(action_type)}")
    return action_type


def check_instance(owner: str, what: str, value: object, expected: type) -> None:
    """TypeError naming ``owner``, ``what`` and both types when ``value`` is not an ``expected``."""
    if not isinstance(value, expected):
        raise TypeError(f"{owner}: {what} must be a {expected.__module__}.{expected.__name__}, got "
                        f"{type(value).__module__}.{type(value).__name__}")


def check_duration(owner: str, what: str, seconds: object) -> float:
    """``seconds`` (s) as a float > 0 and finite."""
    if isinstance(seconds, bool) or not isinstance(seconds, (int, float)):
        raise TypeError(f"{owner}: {what} must be a number of seconds, got {seconds!r}")
    if not (seconds > 0.0 and math.isfinite(seconds)):
        raise ValueError(f"{owner}: {what} must be > 0 s and finite, got {seconds!r}")
    return float(seconds)


def check_timeout(owner: str, what: str, seconds: object) -> float | None:
    """Like ``check_duration``, but None passes: it means "wait for ever"."""
    return None if seconds is None else check_duration(owner, what, seconds)


def check_qos(owner: str, qos: object) -> QosArg:
    """``qos`` if it is a QoSProfile or a history depth (int >= 1)."""
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, bool) or not isinstance(qos, int):
        raise TypeError(f"{owner}: qos must be a rclpy.qos.QoSProfile or a depth (int), got {qos!r}")
    if qos < 1:
        raise ValueError(f"{owner}: qos depth must be >= 1, got {qos}")
    return qos


def check_created(owner: str, part: T | None, kind: str) -> T:
    """``part``, the component a client base makes in ``on_initialize``; SmaccError when it is missing
    because a subclass overrode ``on_initialize`` without calling ``super().on_initialize()``."""
    if part is None:
        raise SmaccError(f"{owner}: no {kind}; call super().on_initialize() in your on_initialize")
    return part
