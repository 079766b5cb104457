"""A one-line live status for long commands (bag record and play, the demos), redrawn in place on a terminal.

On a terminal the line is rewritten at most every ``period`` seconds (wall clock) with a carriage
return; when stderr is a pipe or a file nothing is drawn, so logs and tests stay clean, and only
the final line of :meth:`StatusLine.finish` is printed.
"""

from __future__ import annotations

import shutil
import sys
import time
from typing import TextIO


class StatusLine:
    """Rate-limited status line on ``stream`` (stderr by default)."""

    def __init__(self, stream: TextIO | None = None, period: float = 0.25, live: bool | None = None) -> None:
        """``live`` forces drawing on or off; by default it is on when ``stream`` is a terminal."""
        self._stream = stream if stream is not None else sys.stderr
        self._period = period
        self._live = self._stream.isatty() if live is None else live
        self._last = float("-inf")
        self._drawn = False

    def update(self, text: str, force: bool = False) -> None:
        """Redraw with ``text`` if the period has passed since the last redraw (or ``force``)."""
        if not self._live:
            return
        now = time.monotonic()
        if not force and now - self._last < self._period:
            return
        self._last = now
        width = max(20, shutil.get_terminal_size((100, 20)).columns - 1)
        line = text if len(text) <= width else text[: width - 1] + "…"
        self._stream.write("\r" + line.ljust(width))
        self._stream.flush()
        self._drawn = True

    def clear(self) -> None:
        """Blank the live line, so that a normal line can be printed on the same stream."""
        if self._drawn:
            width = max(20, shutil.get_terminal_size((100, 20)).columns - 1)
            self._stream.write("\r" + " " * width + "\r")
            self._stream.flush()
            self._drawn = False
            self._last = float("-inf")  # redraw at the next update

    def finish(self, text: str) -> None:
        """End the live line and print ``text`` as a normal line."""
        if self._drawn:
            self._stream.write("\r")
        self._stream.write(text + "\n")
        self._stream.flush()
        self._drawn = False


def topic_counts(counts: dict[str, int], limit: int = 8) -> str:
    """``/scan 20  /odom 120 …`` for the busiest ``limit`` topics."""
    busiest = sorted(counts.items(), key=lambda item: (-item[1], item[0]))[:limit]
    text = "  ".join(f"{topic} {count}" for topic, count in busiest)
    return text + ("  …" if len(counts) > limit else "")
