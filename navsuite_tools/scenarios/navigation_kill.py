"""Which process to SIGKILL for a scenario's ``kill_navigation`` event, and the kill itself.

The target is the process that holds bt_navigator and the controller server: ``nav2`` in nav-bringup's
default one-process layout (Nav2's ``use_composition``), ``navigation`` in the isolated and SLAM
layouts. Each of them is a lockstep participant that names itself ``<role>:<pid>`` on
/lockstep/progress (ros_tools.runtime.lockstep), so the injector learns the pid from the ROS graph
it already listens to, whatever command started the stack (navsuite-demo, sm-battery-patrol, or the
worker's own nav-bringup) and however deep in the process tree it sits.

Why a guard: a pid read off DDS is only trusted when the process is a descendant of the scenario's
worker (the injector's parent). A stray report from another run could otherwise name a process of
someone else's, and SIGKILL is not a signal to send on hearsay.
"""

from __future__ import annotations

import os
import signal
from collections.abc import Callable

#: Lockstep roles of the process running bt_navigator and the controller (nav-bringup's components).
NAVIGATION_ROLES = ("nav2", "navigation")


def navigation_pid(participant: str) -> int | None:
    """The pid in a participant name ``<role>:<pid>`` whose role runs navigation, else None."""
    role, _, pid = participant.rpartition(":")
    if role not in NAVIGATION_ROLES or not pid.isdigit():
        return None
    return int(pid)


def parent_of(pid: int) -> int | None:
    """The parent pid of ``pid`` from /proc (None when the process is gone)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="utf-8") as stat:
            text = stat.read()
    except OSError:
        return None
    return int(text[text.rindex(")") + 2:].split()[1])  # after "pid (comm) state": ppid


def descends_from(pid: int, ancestor: int, parent: Callable[[int], int | None] = parent_of) -> bool:
    """True when ``ancestor`` is ``pid``'s parent, grandparent, ... (walks up to init)."""
    current: int | None = pid
    for _ in range(64):  # deeper than any launch tree; a cycle cannot happen, a bound costs nothing
        current = parent(current) if current is not None else None
        if current is None or current <= 1:
            return False
        if current == ancestor:
            return True
    return False


def kill_navigation(pid: int, ancestor: int) -> str:
    """SIGKILL ``pid`` if it descends from ``ancestor``; what was done, for the "applied" line.

    Raises:
        PermissionError: ``pid`` is not in ``ancestor``'s process tree (nothing is sent).
    """
    if not descends_from(pid, ancestor):
        raise PermissionError(f"pid {pid} is not a process of this scenario (not under pid {ancestor})")
    os.kill(pid, signal.SIGKILL)
    return f"pid {pid}"
