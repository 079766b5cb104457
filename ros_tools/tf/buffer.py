"""A transform buffer with tf2's lookup semantics, with no ROS types, so it can be unit-tested.

Frames form a tree: each child frame has one parent, set by the latest transform received for it.
Dynamic transforms are kept for ``cache_time`` seconds and interpolated between stamps; static
transforms hold at every time. ``lookup(target, source, time)`` returns the transform that maps
points in ``source`` into ``target`` (tf2's ``lookup_transform(target, source, time)``); ``time``
None (or 0) means "the latest time at which every transform on the path is known", as in tf2.
Times are seconds of whichever ROS clock the caller uses (sim time under /clock).
"""

from __future__ import annotations

import bisect
import threading
from dataclasses import dataclass, field

from ros_tools.tf.transform import Transform, interpolate


class TransformError(Exception):
    """A lookup could not be answered; the message says why, in tf2's words where they exist."""


class ConnectivityError(TransformError):
    """The two frames are not connected in the current tree (or a frame is unknown)."""


class ExtrapolationError(TransformError):
    """The requested time lies outside the stored history of a transform on the path."""


@dataclass
class _Edge:
    """The history of one child frame's transform to its parent."""

    parent: str
    static: bool
    stamps: list[float] = field(default_factory=list)
    transforms: list[Transform] = field(default_factory=list)

    def at(self, time: float | None, child: str) -> Transform:
        if self.static:
            return self.transforms[-1]
        if time is None:
            return self.transforms[-1]
        newest, oldest = self.stamps[-1], self.stamps[0]
        if time > newest + 1e-9:
            raise ExtrapolationError(
                f"Lookup would require extrapolation into the future. Requested time {time:.6f} "
                f"but the latest data is at time {newest:.6f}, when looking up transform from frame "
                f"[{child}] to frame [{self.parent}]"
            )
        if time < oldest - 1e-9:
            raise ExtrapolationError(
                f"Lookup would require extrapolation into the past. Requested time {time:.6f} "
                f"but the earliest data is at time {oldest:.6f}, when looking up transform from frame "
                f"[{child}] to frame [{self.parent}]"
            )
        i = bisect.bisect_left(self.stamps, time)
        for j in (i - 1, i):  # a stamp within the 1 ns tolerance, on either side (also past either end)
            if 0 <= j < len(self.stamps) and abs(self.stamps[j] - time) <= 1e-9:
                return self.transforms[j]
        t0, t1 = self.stamps[i - 1], self.stamps[i]
        return interpolate(self.transforms[i - 1], self.transforms[i], (time - t0) / (t1 - t0))


class TransformBuffer:
    """Thread-safe store of a frame tree's transforms over time."""

    def __init__(self, cache_time: float = 10.0) -> None:
        self.cache_time = cache_time
        self._edges: dict[str, _Edge] = {}
        self._lock = threading.Lock()

    def set_transform(self, parent: str, child: str, stamp: float, transform: Transform,
                      static: bool = False) -> None:
        """Store ``transform`` (parent ← child) at ``stamp`` seconds."""
        parent, child = parent.lstrip("/"), child.lstrip("/")
        if not parent or not child or parent == child:
            raise ValueError(f"invalid transform frames: parent '{parent}', child '{child}'")
        with self._lock:
            edge = self._edges.get(child)
            if edge is None or edge.parent != parent or edge.static != static:
                edge = _Edge(parent, static)
                self._edges[child] = edge
            if static:
                edge.stamps[:] = [stamp]
                edge.transforms[:] = [transform]
                return
            if edge.stamps and stamp < edge.stamps[-1] - self.cache_time:
                return  # older than the cache: tf2 drops these too
            i = bisect.bisect_right(edge.stamps, stamp)
            if i > 0 and edge.stamps[i - 1] == stamp:
                edge.transforms[i - 1] = transform
            else:
                edge.stamps.insert(i, stamp)
                edge.transforms.insert(i, transform)
            cutoff = edge.stamps[-1] - self.cache_time
            drop = bisect.bisect_left(edge.stamps, cutoff)
            if drop > 0 and len(edge.stamps) - drop >= 2:
                del edge.stamps[:drop]
                del edge.transforms[:drop]

    def clear(self) -> None:
        """Forget all dynamic transforms (e.g. after the simulation was reset); keep static ones."""
        with self._lock:
            self._edges = {child: edge for child, edge in self._edges.items() if edge.static}

    def frames(self) -> dict[str, str]:
        """Every known child frame and its parent."""
        with self._lock:
            return {child: edge.parent for child, edge in self._edges.items()}

    def _chain(self, frame: str) -> list[str]:
        chain = [frame]
        while chain[-1] in self._edges:
            chain.append(self._edges[chain[-1]].parent)
            if len(chain) > 1000:
                raise ConnectivityError(f"frame tree has a loop through [{frame}]")
        return chain

    def _latest_common_time(self, frames: list[str]) -> float | None:
        stamps = [self._edges[f].stamps[-1] for f in frames if not self._edges[f].static]
        return min(stamps) if stamps else None

    def lookup(self, target: str, source: str, time: float | None = None) -> Transform:
        """Transform mapping points in ``source`` into ``target`` at ``time`` (None/0: latest)."""
        target, source = target.lstrip("/"), source.lstrip("/")
        if time == 0.0:
            time = None
        with self._lock:
            if target == source:
                return Transform()
            up_source, up_target = self._chain(source), self._chain(target)
            common = next((f for f in up_source if f in set(up_target)), None)
            if common is None:
                known = sorted(set(self._edges) | {e.parent for e in self._edges.values()})
                missing = [f for f in (target, source) if f not in known]
                reason = (f"frame [{missing[0]}] does not exist" if missing
                          else "they are not part of the same tree")
                raise ConnectivityError(
                    f'Could not find a connection between "{target}" and "{source}" because {reason}. '
                    f"Known frames: {', '.join(known) or 'none'}"
                )
            source_path = up_source[: up_source.index(common)]
            target_path = up_target[: up_target.index(common)]
            when = time if time is not None else self._latest_common_time(source_path + target_path)
            # common ← source, composed from the source upwards.
            common_from_source = Transform()
            for child in reversed(source_path):
                common_from_source = common_from_source * self._edges[child].at(when, child)
            common_from_target = Transform()
            for child in reversed(target_path):
                common_from_target = common_from_target * self._edges[child].at(when, child)
            return common_from_target.inverse() * common_from_source

    def can_transform(self, target: str, source: str, time: float | None = None) -> bool:
        """True when ``lookup`` would succeed now."""
        try:
            self.lookup(target, source, time)
        except TransformError:
            return False
        return True
