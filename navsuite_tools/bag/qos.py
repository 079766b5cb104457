"""QoS for recording and playback, and its rosbag2 text form (``offered_qos_profiles``).

Why this matters: a subscriber only receives from publishers whose QoS it is compatible with, and
latched topics (``/map``, ``/tf_static``, ``/amcl_pose``) deliver their last message only to a
transient-local subscriber. The recorder therefore asks for what the publishers offer (reliable
only if every publisher is reliable, transient local only if every one is), as rosbag2 does, and
stores the publishers' profiles with each channel so that playback can offer the same again.

The text is rosbag2's metadata version 9 (Jazzy): a YAML list with one mapping per publisher,
policies as lowercase names (``keep_last``, ``reliable``, ``transient_local``, ``automatic``,
``unknown``) and durations as ``{sec, nsec}``. Older integer policy values are accepted on reading.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from enum import IntEnum
from typing import Any

import yaml
from rclpy.duration import Duration
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
)

#: History depth of recorder subscriptions: room for bursts while the writer compresses a chunk.
RECORD_DEPTH = 100
#: Minimum history depth of playback publishers (rosbag2's default history depth).
PLAY_DEPTH = 10

_NS = 1_000_000_000
_POLICIES: dict[str, type[IntEnum]] = {
    "history": HistoryPolicy,
    "reliability": ReliabilityPolicy,
    "durability": DurabilityPolicy,
    "liveliness": LivelinessPolicy,
}
_DURATIONS = ("deadline", "lifespan", "liveliness_lease_duration")


def _duration_to_yaml(duration: Duration) -> dict[str, int]:
    ns = duration.nanoseconds
    return {"sec": ns // _NS, "nsec": ns % _NS}


def qos_to_dict(profile: QoSProfile) -> dict[str, Any]:
    """One publisher's profile as rosbag2 writes it (keys in rosbag2's order)."""
    return {
        "history": profile.history.name.lower(),
        "depth": int(profile.depth),
        "reliability": profile.reliability.name.lower(),
        "durability": profile.durability.name.lower(),
        "deadline": _duration_to_yaml(profile.deadline),
        "lifespan": _duration_to_yaml(profile.lifespan),
        "liveliness": profile.liveliness.name.lower(),
        "liveliness_lease_duration": _duration_to_yaml(profile.liveliness_lease_duration),
        "avoid_ros_namespace_conventions": bool(profile.avoid_ros_namespace_conventions),
    }


def offered_qos_yaml(profiles: Iterable[QoSProfile]) -> str:
    """The ``offered_qos_profiles`` channel metadata for the given publisher profiles."""
    entries = [qos_to_dict(profile) for profile in profiles]
    return yaml.safe_dump(entries, sort_keys=False) if entries else ""


def _policy(key: str, value: Any, where: str) -> IntEnum:
    enum = _POLICIES[key]
    try:
        if isinstance(value, int):
            return enum(value)
        return enum[str(value).upper()]
    except (KeyError, ValueError):
        names = ", ".join(member.name.lower() for member in enum)
        raise ValueError(f"{where}: {key} '{value}' is not one of {names}") from None


def _duration(value: Any, key: str, where: str) -> Duration:
    if not isinstance(value, dict) or not {"sec", "nsec"} <= value.keys():
        raise ValueError(f"{where}: {key} must be a mapping with sec and nsec, got {value!r}")
    ns = int(value["sec"]) * _NS + int(value["nsec"])
    return Duration(nanoseconds=min(ns, 2**63 - 1))


def parse_offered_qos(text: str, where: str = "offered_qos_profiles") -> list[QoSProfile]:
    """Read ``offered_qos_profiles`` text back into profiles (empty text: no profiles).

    Unknown history (what DDS discovery reports for remote publishers) becomes keep-last.

    Raises:
        ValueError: the text is not such a YAML list; ``where`` prefixes the message.
    """
    if not text.strip():
        return []
    try:
        entries = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ValueError(f"{where}: not YAML ({exc})") from None
    if not isinstance(entries, list) or not all(isinstance(entry, dict) for entry in entries):
        raise ValueError(f"{where}: expected a list of QoS mappings")
    profiles = []
    for entry in entries:
        history = _policy("history", entry.get("history", "keep_last"), where)
        if history not in (HistoryPolicy.KEEP_LAST, HistoryPolicy.KEEP_ALL):
            history = HistoryPolicy.KEEP_LAST
        kwargs = {key: _duration(entry[key], key, where) for key in _DURATIONS if key in entry}
        profiles.append(QoSProfile(
            history=history,
            depth=max(int(entry.get("depth", 0)), PLAY_DEPTH),
            reliability=_policy("reliability", entry.get("reliability", "reliable"), where),
            durability=_policy("durability", entry.get("durability", "volatile"), where),
            liveliness=_policy("liveliness", entry.get("liveliness", "automatic"), where),
            avoid_ros_namespace_conventions=bool(entry.get("avoid_ros_namespace_conventions", False)),
            **kwargs,
        ))
    return profiles


def request_for_offers(offers: Sequence[QoSProfile], depth: int = RECORD_DEPTH) -> QoSProfile:
    """The subscription profile that receives from every publisher in ``offers``.

    Reliable only if all publishers are reliable (a reliable reader does not match a best-effort
    writer); transient local only if all are (same rule for durability), so latched messages
    are received whenever that is possible without losing a publisher.
    """
    reliable = bool(offers) and all(o.reliability == ReliabilityPolicy.RELIABLE for o in offers)
    latched = bool(offers) and all(o.durability == DurabilityPolicy.TRANSIENT_LOCAL for o in offers)
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE,
    )


def playback_profile(offers: Sequence[QoSProfile]) -> QoSProfile:
    """The publisher profile for replaying a topic recorded with these publisher profiles.

    One recorded publisher profile (or several that agree on reliability and durability) is
    offered again; otherwise, or with none recorded, a reliable volatile publisher is used.
    """
    if offers:
        first = offers[0]
        if all(o.reliability == first.reliability and o.durability == first.durability for o in offers):
            known = (ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT)
            return QoSProfile(
                history=first.history,
                depth=max(max(o.depth for o in offers), PLAY_DEPTH),
                reliability=first.reliability if first.reliability in known else ReliabilityPolicy.RELIABLE,
                durability=(DurabilityPolicy.TRANSIENT_LOCAL
                            if first.durability == DurabilityPolicy.TRANSIENT_LOCAL
                            else DurabilityPolicy.VOLATILE),
            )
    return QoSProfile(depth=PLAY_DEPTH)
