"""``ISmaccUpdatable``: objects the runtime polls, like SMACC2's SignalDetector loop.

The ROS runtime calls ``SmaccStateMachineBase.update()`` at ``signal_detector_loop_freq`` (20 Hz by
default); every client, component, and every behavior, reactor and generator of the active states that
mixes this class in gets ``update()`` called, at most once per its own ``update_period_s`` (s) measured on
the machine's injected clock, so sim time works. ``None`` means "on every poll".
"""

from __future__ import annotations

import logging
import math
from collections.abc import Container, Iterable

#: Slack (s) when comparing elapsed time with a period: 0.1 s polled at 20 Hz on a nanosecond clock is
#: 0.09999999999990905 s between polls now and then, and must still count as a full period.
PERIOD_SLACK_S = 1e-6

_log = logging.getLogger("smacc_py")


class ISmaccUpdatable:
    """Mix-in for objects with periodic work; override ``update()``. SMACC2: ``smacc2::ISmaccUpdatable``."""

    update_period_s: float | None = None
    _last_update_s: float = -math.inf

    def update(self) -> None:
        """Periodic work. Runs on the polling thread (the ROS runtime's executor thread); must not block."""

    def set_update_period(self, period_s: float | None) -> None:
        """Poll at most every ``period_s`` seconds (None: every poll). ValueError when not positive."""
        if period_s is not None and not period_s > 0.0:
            raise ValueError(f"{type(self).__name__}: update period must be > 0 s, got {period_s!r}")
        self.update_period_s = period_s

    def _update_due(self, now_s: float) -> bool:
        period = self.update_period_s
        if period is not None and now_s - self._last_update_s < period - PERIOD_SLACK_S:
            return False
        self._last_update_s = now_s
        return True


def poll_updatables(objects: Iterable[object], now_s: float, active_seqs: Container[int]) -> None:
    """Call ``update()`` on each ISmaccUpdatable among ``objects`` whose period has elapsed at ``now_s``.

    A state-lifetime part (one with a ``_seq``) whose state is no longer in ``active_seqs`` is skipped: it
    may have exited since ``objects`` was collected. An ``update()`` that raises is logged and skipped.
    """
    for obj in objects:
        if isinstance(obj, ISmaccUpdatable) and obj._update_due(now_s):
            seq = getattr(obj, "_seq", None)
            if seq is not None and seq not in active_seqs:
                continue
            try:
                obj.update()
            except Exception:
                _log.exception("%s.update raised; skipped", type(obj).__name__)
