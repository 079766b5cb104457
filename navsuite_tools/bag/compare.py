"""Compare two recordings of the same lockstep run and name the first sim time where they part.

Why: a mission that ends SUCCESS once and ABORT the next diverged somewhere long before; this finds
where. The stamped topics of two MCAP recordings are lined up by their header stamp (sim time, ns),
and per topic the first stamp whose values differ by more than a tolerance is reported with the
largest difference seen. Unstamped topics (a Twist ``/cmd_vel``) are lined up by their order instead,
and their receive (log) times are shown: a recorder is not a lockstep participant, so a log time says
only roughly when a message went out. ``scripts/repeatability.py`` and ``navsuite-scenarios rerun``
print what this module finds.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from navsuite_tools.bag.reader import BagReader
from ros_tools.geometry import yaw_of

DEFAULT_TOPICS = ("/odom", "/ground_truth", "/cmd_vel", "/amcl_pose", "/scan", "/plan", "/local_plan")


def values(msg: Any) -> tuple[float, ...]:
    """The numbers of a message that matter for repeatability (poses, twists, ranges, paths)."""
    kind = type(msg).__name__
    if kind == "Odometry":
        p, t = msg.pose.pose, msg.twist.twist
        return (p.position.x, p.position.y, yaw_of(p.orientation), t.linear.x, t.angular.z)
    if kind == "PoseWithCovarianceStamped":
        p = msg.pose.pose
        return (p.position.x, p.position.y, yaw_of(p.orientation))
    if kind in ("Twist", "TwistStamped"):
        t = msg.twist if kind == "TwistStamped" else msg
        return (t.linear.x, t.angular.z)
    if kind == "LaserScan":
        return tuple(0.0 if math.isinf(r) else r for r in msg.ranges)
    if kind == "Path":
        return tuple(v for s in msg.poses for v in (s.pose.position.x, s.pose.position.y))
    raise ValueError(f"no comparison for {kind}")


def stamp_ns(msg: Any) -> int | None:
    header = getattr(msg, "header", None)
    return None if header is None else header.stamp.sec * 1_000_000_000 + header.stamp.nanosec


@dataclass
class Series:
    """One topic of one recording: (key, log time ns, values); key = stamp (ns) or index."""

    stamped: bool
    items: list[tuple[int, int, tuple[float, ...]]]


def load(path: Path, topics: Iterable[str]) -> dict[str, Series]:
    with BagReader(path) as bag:
        present = [t for t in topics if t in bag.topics]
        out: dict[str, Series] = {}
        for item, msg in bag.decoded(present):
            stamp = stamp_ns(msg)
            series = out.setdefault(item.topic, Series(stamp is not None, []))
            key = stamp if stamp is not None else len(series.items)
            series.items.append((key, item.log_time, values(msg)))
    return out


def _diff(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    if len(a) != len(b):
        return math.inf
    return max((abs(x - y) for x, y in zip(a, b, strict=True)), default=0.0)


@dataclass
class Verdict:
    topic: str
    compared: int
    first: tuple[int, int, int] | None   # (key, log time a, log time b) of the first difference
    max_diff: float
    detail: str


def compare(topic: str, a: Series, b: Series, tol: float) -> Verdict:
    """Line ``a`` and ``b`` up by key over their common span; the first key beyond ``tol``."""
    bmap: dict[int, tuple[int, tuple[float, ...]]] = {}
    for key, log, vals in b.items:
        bmap.setdefault(key, (log, vals))   # a repeated stamp: the first message counts
    first, max_diff, compared, seen, detail = None, 0.0, 0, set(), ""
    for key, log, vals in a.items:
        other = bmap.get(key)
        if other is None or key in seen:   # a recorder that joined late or left early: not a difference
            continue
        seen.add(key)
        diff = _diff(vals, other[1])
        compared += 1
        max_diff = max(max_diff, diff)
        if diff > tol and first is None:
            first = (key, log, other[0])
            detail = f"A={tuple(round(v, 6) for v in vals[:5])} B={tuple(round(v, 6) for v in other[1][:5])}"
    return Verdict(topic, compared, first, max_diff, detail)


def report(verdicts: Sequence[Verdict], stamped: dict[str, bool]) -> str:
    lines = []
    def order(v: Verdict) -> tuple[bool, int]:
        return v.first is None, v.first[0] if v.first and stamped[v.topic] else 0

    for v in sorted(verdicts, key=order):
        if v.compared == 0:
            lines.append(f"{v.topic:14s} no message in common (no stamp, or no index, appears in both)")
            continue
        if v.first is None:
            lines.append(f"{v.topic:14s} identical over {v.compared} messages")
            continue
        key, log_a, log_b = v.first
        where = f"stamp {key * 1e-9:.3f} s" if stamped[v.topic] else f"message #{key}"
        lines.append(f"{v.topic:14s} first differs at {where} (received A {log_a * 1e-9:.3f} s, "
                     f"B {log_b * 1e-9:.3f} s); max diff {v.max_diff:.3g} over {v.compared}: {v.detail}")
    return "\n".join(lines)


def verdict(verdicts: Sequence[Verdict], stamped: dict[str, bool], missing: Sequence[str] = ()) -> str:
    """The one-line verdict: ``identical: ...`` or ``differ: ...`` with the earliest parting (sim time
    of the first differing stamp; an unstamped topic is named by its message index)."""
    parted = [v for v in verdicts if v.first is not None]
    empty = [v.topic for v in verdicts if v.compared == 0]
    if not parted and not empty and not missing and verdicts:
        total = sum(v.compared for v in verdicts)
        return f"identical: {len(verdicts)} topics, {total} messages compared, none beyond the tolerance"
    reasons = []
    timed = sorted((v.first[0], v.topic) for v in parted if v.first is not None and stamped[v.topic])
    if timed:
        stamp, topic = timed[0]
        reasons.append(f"first part at sim time {stamp * 1e-9:.3f} s on {topic}")
    untimed = [v for v in parted if v.first is not None and not stamped[v.topic]]
    reasons += [f"{v.topic} from message #{v.first[0]}" for v in untimed if v.first is not None]
    if empty:
        reasons.append(f"no message in common on {', '.join(empty)}")
    if missing:
        reasons.append(f"only one recording has {', '.join(missing)}")
    if not verdicts and not missing:
        reasons.append("no compared topic in either recording")
    return "differ: " + "; ".join(reasons)


@dataclass(frozen=True)
class Comparison:
    """Two recordings compared: ``report`` has a line per topic, ``verdict`` the one-line verdict."""

    report: str
    verdict: str

    @property
    def identical(self) -> bool:
        return self.verdict.startswith("identical")


def compare_recordings(a: Path, b: Path, topics: Sequence[str] = DEFAULT_TOPICS,
                       tol: float = 1e-9) -> Comparison:
    """Compare the ``topics`` of recordings ``a`` and ``b`` (see the module docstring)."""
    run_a, run_b = load(a, topics), load(b, topics)
    verdicts = [compare(t, run_a[t], run_b[t], tol) for t in topics if t in run_a and t in run_b]
    missing = [t for t in topics if (t in run_a) != (t in run_b)]
    stamped = {t: run_a[t].stamped for t in run_a}
    return Comparison(report(verdicts, stamped) if verdicts else "", verdict(verdicts, stamped, missing))
