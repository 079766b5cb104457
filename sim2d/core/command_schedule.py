"""Stamped velocity commands, applied at their stamp plus a fixed delay instead of on arrival.

Why: in lockstep the simulator may run up to ``lockstep.max_lead`` of sim time ahead of the
controller's progress report. A command applied when it arrives therefore takes effect at a sim
time that depends on wall timing (how far the sim had stepped by the time DDS delivered it), and
two runs of the same mission drift apart from the first command on (issue 17: one seed ended
SUCCESS in some runs and ABORT in others). A TwistStamped command (Nav2 Jazzy's
``enable_stamped_cmd_vel``) carries the sim time it was computed for; applying it at exactly
``stamp + delay`` makes the effect independent of wall timing, as long as it arrives before the
simulator reaches that time. The lockstep guarantees that when ``delay`` covers ``max_lead`` plus
the time a participant may report beyond its last control cycle; a command that still arrives late
is applied at once and counted (``late``), so a run can tell whether it was exact.

Pure (stdlib only): times are integer nanoseconds of sim time; velocities m/s and rad/s.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field


@dataclass(order=True)
class ScheduledCommand:
    """One command: applied at ``apply_ns`` (sim time, ns); ``seq`` keeps arrival order on ties."""

    apply_ns: int
    seq: int
    v: float = field(compare=False)  # m/s
    w: float = field(compare=False)  # rad/s


class CommandSchedule:
    """Commands waiting for their sim time.

    Args:
        delay_ns: sim time (ns) between a command's stamp and the moment it takes effect.
    """

    def __init__(self, delay_ns: int) -> None:
        if delay_ns < 0:
            raise ValueError(f"delay must be >= 0 ns, got {delay_ns}")
        self.delay_ns = delay_ns
        self.late = 0            # commands that arrived after their apply time (applied at once)
        self.worst_late_ns = 0   # the latest of them: how much later than its apply time it arrived
        self._queue: list[ScheduledCommand] = []
        self._seq = 0

    def __len__(self) -> int:
        return len(self._queue)

    def add(self, stamp_ns: int, v: float, w: float, now_ns: int) -> int:
        """Queue a command stamped ``stamp_ns`` that arrived at sim time ``now_ns``.

        Returns:
            The sim time (ns) it takes effect: ``stamp_ns + delay_ns``, or ``now_ns`` when that has
            passed already (then it is counted as late).
        """
        apply_ns = stamp_ns + self.delay_ns
        if apply_ns < now_ns:
            self.late += 1
            self.worst_late_ns = max(self.worst_late_ns, now_ns - apply_ns)
            apply_ns = now_ns
        heapq.heappush(self._queue, ScheduledCommand(apply_ns, self._seq, v, w))
        self._seq += 1
        return apply_ns

    def due(self, now_ns: int) -> list[ScheduledCommand]:
        """Remove and return the commands whose time has come (``apply_ns <= now_ns``), in order."""
        out = []
        while self._queue and self._queue[0].apply_ns <= now_ns:
            out.append(heapq.heappop(self._queue))
        return out

    def clear(self) -> None:
        """Forget the waiting commands (a reset of the simulator)."""
        self._queue.clear()
