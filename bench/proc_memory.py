"""Resident memory of a process tree (a launched stack), from /proc, and its growth between two looks.

Why: a soak run must show that no process of the stack leaks. The resident set (VmRSS of
/proc/<pid>/status) of every process descending from the launcher is read after the first goal
(warm: imports done, costmaps allocated) and at the end; processes are named by their command line
(bench.bench_cpu.process_name: ``sim2d``, ``nav2 (all nodes)``, ``nav-bringup (launcher)`` ...).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from bench.bench_cpu import process_name


def _parent(pid: int) -> int | None:
    """The parent pid of ``pid``; None when it is gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return int(text.rsplit(")", 1)[1].split()[1])  # after "(comm)", which may contain spaces


def descendants(root: int) -> list[int]:
    """``root`` and every live process below it, to any depth (root first)."""
    pids = [int(entry.name) for entry in os.scandir("/proc") if entry.name.isdigit()]
    parents = {pid: _parent(pid) for pid in pids}
    family = [root]
    for pid in family:  # grows while it is walked: breadth first
        family.extend(child for child, parent in sorted(parents.items()) if parent == pid)
    return [pid for pid in family if parents.get(pid) is not None]


def rss_mib(pid: int) -> float | None:
    """VmRSS of ``pid`` in MiB; None when it is gone (or a zombie, which has no VmRSS)."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0  # kB
    except OSError:
        return None
    return None


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace").strip()
    except OSError:
        return ""


def tree_memory(root: int) -> dict[str, float]:
    """Process name -> RSS (MiB) of ``root``'s tree; a name seen twice gets ``#<pid>`` appended."""
    memory: dict[str, float] = {}
    for pid in descendants(root):
        rss, cmdline = rss_mib(pid), _cmdline(pid)
        if rss is None or not cmdline:
            continue
        name = process_name(cmdline)
        memory[f"{name} #{pid}" if name in memory else name] = rss
    return memory


@dataclass(frozen=True)
class MemoryGrowth:
    """One process's RSS (MiB) warm and at the end; None where it did not run."""

    name: str
    warm: float | None
    end: float | None

    @property
    def percent(self) -> float | None:
        """Growth from warm to end in % of warm; None unless both were measured."""
        if self.warm is None or self.end is None or self.warm <= 0.0:
            return None
        return 100.0 * (self.end - self.warm) / self.warm


def compare(warm: dict[str, float], end: dict[str, float]) -> list[MemoryGrowth]:
    """Every process of either look, in the order first seen (warm's, then those only at the end)."""
    names = list(warm) + [name for name in end if name not in warm]
    return [MemoryGrowth(name, warm.get(name), end.get(name)) for name in names]


def largest_growth(growths: list[MemoryGrowth]) -> MemoryGrowth | None:
    """The process that grew most (in %), among those measured both times."""
    measured = [growth for growth in growths if growth.percent is not None]
    return max(measured, key=lambda growth: growth.percent or 0.0) if measured else None
