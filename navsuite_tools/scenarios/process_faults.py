"""Which process a kill_<process> / freeze_<process> event hits, and the signals themselves.

Targets (schema_fields.PROCESSES):

* ``navigation``: the process running bt_navigator and the controller (lockstep role ``nav2`` in
  nav-bringup's one-process layout, ``navigation`` in the isolated and SLAM layouts);
* ``localization``: the process running map_server and AMCL (role ``localization``; the isolated layout,
  which the worker picks for a scenario with such an event);
* ``simulator``: sim2d. It is the lockstep leader, not a participant, so it names itself nowhere on the
  graph; it is found in this machine's process table as the scenario's process running
  ``sim2d.ros.cli``.

Every pid is only trusted when the process descends from the scenario's worker (the injector's parent):
navsuite_tools.scenarios.navigation_kill says why. A freeze is SIGSTOP, then SIGCONT after the event's wall
seconds (sim time stands still meanwhile: a frozen simulator sends no /clock, a frozen participant holds
the lockstep simulator); ``FreezeBook.thaw_all`` continues whatever is still stopped when the injector
ends, so no frozen process outlives the run.
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Callable
from pathlib import Path

from navsuite_tools.scenarios.navigation_kill import NAVIGATION_ROLES, descends_from


def process_exists(pid: int) -> bool:
    """Whether ``pid`` names a process on this machine (signal 0: an existence check only)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True

#: lockstep roles (``<role>:<pid>`` on /lockstep/progress) of each participant target
TARGET_ROLES = {"navigation": NAVIGATION_ROLES, "localization": ("localization",)}
SIMULATOR_MODULE = "sim2d.ros.cli"


def target_of(kind: str) -> str:
    """``kill_navigation`` -> ``navigation``."""
    return kind.split("_", 1)[1]


def role_pid(target: str, participant: str) -> int | None:
    """The pid in a participant name ``<role>:<pid>`` whose role is ``target``'s, else None."""
    role, _, pid = participant.rpartition(":")
    if role not in TARGET_ROLES.get(target, ()) or not pid.isdigit():
        return None
    return int(pid)


def simulator_pid(ancestor: int, proc: Path = Path("/proc")) -> int | None:
    """The pid of the process under ``ancestor`` whose command line runs sim2d, else None."""
    for entry in proc.iterdir():
        if not entry.name.isdigit():
            continue
        try:
            cmdline = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if SIMULATOR_MODULE.encode() in cmdline and descends_from(int(entry.name), ancestor):
            return int(entry.name)
    return None


def send(pid: int, sig: int, ancestor: int) -> None:
    """``sig`` to ``pid`` if it descends from ``ancestor``; PermissionError (nothing sent) otherwise."""
    if not descends_from(pid, ancestor):
        raise PermissionError(f"pid {pid} is not a process of this scenario (not under pid {ancestor})")
    os.kill(pid, sig)


class FreezeBook:
    """The processes this injector stopped and has not continued yet."""

    def __init__(self, kill: Callable[[int, int], None] = os.kill) -> None:
        self._kill = kill
        self.frozen: set[int] = set()

    def freeze(self, pid: int, ancestor: int) -> None:
        send(pid, signal.SIGSTOP, ancestor)
        self.frozen.add(pid)

    def thaw(self, pid: int) -> bool:
        """SIGCONT ``pid`` if this book froze it; whether it was still there to continue."""
        if pid not in self.frozen:
            return False
        self.frozen.discard(pid)
        try:
            self._kill(pid, signal.SIGCONT)
        except ProcessLookupError:
            return False
        return True

    def thaw_all(self) -> None:
        for pid in list(self.frozen):
            with contextlib.suppress(OSError):
                self.thaw(pid)
