"""The processes a process started, read from /proc, and the end of those a test left running.

Why the guard: a process a test starts and does not stop lives on in its worker's ROS domain and
answers the next tests' requests. Seen in the project's CI of 8f4af32: a held NavigateToPose server
whose start-up check failed was never killed; the next three tests of that worker sent their goals
to two servers ("Ignoring unexpected goal response"), and two state machines crashed (SIGSEGV in
rclpy's EventsExecutor).
"""

from __future__ import annotations

import glob
import os
import signal

#: Python's own helper processes, started once and kept for the whole session.
LONG_LIVED = ("multiprocessing.resource_tracker", "multiprocessing.forkserver")


def child_pids(pid: int) -> list[int]:
    """Direct children of ``pid``, started from any of its threads (Linux /proc)."""
    children: list[int] = []
    for path in glob.glob(f"/proc/{pid}/task/*/children"):
        try:
            with open(path, encoding="utf-8") as f:
                children.extend(int(p) for p in f.read().split())
        except OSError:  # the thread ended while we looked
            continue
    return children


def cmdline(pid: int) -> str:
    """The command line of ``pid``, arguments joined by spaces; "" once it has gone."""
    try:
        with open(f"/proc/{pid}/cmdline", encoding="utf-8") as f:
            return f.read().replace("\0", " ").strip()
    except OSError:
        return ""


def _is_zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", encoding="utf-8") as f:
            text = f.read()
    except OSError:
        return True
    return text[text.rindex(")") + 2] == "Z"


def live_children(pid: int) -> set[int]:
    """Children of ``pid`` that still run (a child that exited and was not reaped yet is left out)."""
    return {child for child in child_pids(pid) if not _is_zombie(child)}


def kill_leftovers(before: set[int]) -> list[str]:
    """SIGKILL this process's running children that were not in ``before`` (their process groups
    too, when a child leads one, as ros_tools.launch's processes do) and reap them; their command
    lines, for the warning."""
    killed: list[str] = []
    for child in sorted(live_children(os.getpid()) - before):
        if any(helper in cmdline(child) for helper in LONG_LIVED):
            continue
        killed.append(f"{child}: {cmdline(child)[:200]}")
        try:
            if os.getpgid(child) == child:
                os.killpg(child, signal.SIGKILL)
            else:
                os.kill(child, signal.SIGKILL)
            os.waitpid(child, 0)
        except (ProcessLookupError, ChildProcessError):  # it ended, or its Popen reaped it
            continue
    return killed
