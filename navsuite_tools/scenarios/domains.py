"""ROS_DOMAIN_IDs for concurrent scenarios: each run holds one id no other run on this machine holds.

The claim is an exclusive ``flock`` on ``$TMPDIR/navsuite-ros-domain-<id>.lock``, the same files test
sessions (tests/conftest.py) and benchmarks (bench/harness.py) lock, so a farm, a test run, a benchmark
and another farm never share a DDS domain. The default range, 51..100, stays within 1..100 for the
benchmarks' reason: Fast DDS binds UDP ports 7400 + 250 * id + small offsets, and from id 102 on they
fall into Linux's ephemeral port range (32768..60999), where another socket may already hold them.
Sessions started with a fixed NAVSUITE_TEST_DOMAIN_ID take no lock: give the farm a range that avoids
that id (``--domains``, $NAVSUITE_SCENARIO_DOMAINS).
"""

from __future__ import annotations

import fcntl
import os
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TextIO

DEFAULT_RANGE = (51, 100)
DEFAULT_TEXT = f"{DEFAULT_RANGE[0]}-{DEFAULT_RANGE[1]}"
MAX_DOMAIN_ID = 232  # Fast DDS default port mapping: 7400 + 250 * id stays under 65535
CLAIM_POLL = 0.5  # wall s between attempts while every id of the range is taken


def parse_range(text: str) -> tuple[int, int]:
    """``"86-99"`` or ``"120"`` → (first, last), inclusive; ValueError naming the text otherwise."""
    first, _, last = text.partition("-")
    try:
        low, high = int(first), int(last or first)
    except ValueError:
        raise ValueError(f"expected FIRST-LAST domain ids, got {text!r}") from None
    if not 0 <= low <= high <= MAX_DOMAIN_ID:
        raise ValueError(f"expected 0 <= FIRST <= LAST <= {MAX_DOMAIN_ID}, got {text!r}")
    return low, high


def lock_path(domain: int) -> str:
    return os.path.join(tempfile.gettempdir(), f"navsuite-ros-domain-{domain}.lock")


class DomainPool:
    """Hands out the ids of ``first..last`` (inclusive), one holder at a time, across processes."""

    def __init__(self, first: int, last: int, timeout: float = 600.0) -> None:
        self.first, self.last, self.timeout = first, last, timeout
        self._lock = threading.Lock()  # flock is per open file: threads of one process must not race

    @contextmanager
    def claim(self) -> Iterator[int]:
        """Hold a free id for the block; waits (up to ``timeout`` wall s) while all are held."""
        deadline = time.monotonic() + self.timeout
        while True:
            with self._lock:
                claimed = self._try_claim()
            if claimed is not None:
                break
            if time.monotonic() > deadline:
                raise RuntimeError(f"no free ROS domain id in {self.first}..{self.last} "
                                   f"for {self.timeout:.0f} s")
            time.sleep(CLAIM_POLL)
        domain, handle = claimed
        try:
            yield domain
        finally:
            handle.close()  # releases the flock

    def _try_claim(self) -> tuple[int, TextIO] | None:
        for domain in range(self.first, self.last + 1):
            handle = open(lock_path(domain), "w")  # noqa: SIM115 - held open while the id is in use
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                handle.close()
                continue
            return domain, handle
        return None
