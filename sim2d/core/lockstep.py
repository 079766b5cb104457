"""The simulator side of lockstep: how far the sim may step, given what its participants reported.

Why: a simulator that runs by the wall clock outruns a loaded stack, and a mission's outcome then
depends on how busy the machine is. In lockstep the simulator never steps more than ``max_lead``
of sim time (one control period) beyond the slowest participant's report, so it runs as fast as
the stack keeps up and never faster. A participant that falls silent (crashed, hung, killed
without leaving) must not stop the world: it is dropped, named once in a warning, and the sim goes
on without it. When its process is gone (the pid in its name no longer exists on this machine) that
happens after ``dead_grace`` wall seconds; a live but silent process is waited for ``timeout`` wall
seconds. Why two bounds: a busy machine can starve a live stack for seconds (seen: 5 s with three
stacks and a test run on two cores), and a sim that then went on without it drove the robot blind on
its last command into a pillar. Waiting long for a live process keeps the outcome independent of
load; checking the pid keeps a crash from stalling the world for as long.

A role the sim was told to expect whose process is gone is expected again: a supervisor that
respawns it (nav-bringup's respawn, as nav2_bringup's ``use_respawn``) starts a new process under a
new name, and the world must not run on while the restarted stack is still starting. The sim holds
as before its first step, for at most ``startup_timeout`` wall seconds, then goes on without it.

The protocol (participant side: ``ros_tools/runtime/lockstep.py``): each participant, named
``<role>:<pid>``, reports the newest sim time it has fully processed; a report of 0 ns says it
leaves. The gate is pure (stdlib only): the caller passes the wall time (s, any monotonic origin)
into every call, so tests drive it deterministically. Sim times are integer nanoseconds.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass

HOLD = -1  # limit_ns while expected roles are missing: below any sim time, so no step at all
LEAVE_NS = 0  # a report of this sim time means "I leave"


def role_of(name: str) -> str:
    """The role part of a participant name (``nav2:4242`` -> ``nav2``; a name without ':' is its own role)."""
    return name.rsplit(":", 1)[0]


def process_alive(name: str) -> bool:
    """Whether the process in a participant name (``<role>:<pid>``) still exists on this machine;
    True when the name carries no pid (nothing to check: only ``timeout`` applies)."""
    pid = name.rsplit(":", 1)[-1]
    if ":" not in name or not pid.isdigit():
        return True
    try:
        os.kill(int(pid), 0)  # signal 0: existence and permission check only
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@dataclass
class _Participant:
    reported_ns: int    # newest sim time it has fully processed (ns)
    heard_wall: float   # wall time of its last report (s)


@dataclass(frozen=True)
class Dropped:
    """Someone the sim stopped waiting for, to be named once in a warning.

    Attributes:
        role: the participant's role.
        name: the participant's full name, or None for an expected role that never reported.
        silent_for: wall seconds without a report (since the gate started, for a missing role).
        gone: its process no longer exists (dropped after ``dead_grace``, not ``timeout``).
        awaited: its role is expected, so the sim holds until a new process of that role joins (a
            respawn) or ``startup_timeout`` passes.
    """

    role: str
    name: str | None
    silent_for: float
    gone: bool = False
    awaited: bool = False  # an expected role whose process is gone: held for until a new one joins


class LockstepGate:
    """Tracks the participants' reports and answers how far the simulator may step.

    Args:
        max_lead_ns: how far (ns of sim time) the sim may run ahead of the slowest participant.
        timeout: wall seconds of silence after which a live participant is dropped.
        wall_now: the wall time (s) the gate starts at; the startup timeout counts from here.
        expected: roles that must each have reported before the sim takes its first step.
        startup_timeout: wall seconds to wait for the expected roles before giving up on them.
        dead_grace: wall seconds of silence after which a participant whose process is gone is dropped.
        alive: whether a participant's process still exists (default :func:`process_alive`).
    """

    def __init__(self, max_lead_ns: int, timeout: float, wall_now: float,
                 expected: Iterable[str] = (), startup_timeout: float = 60.0, dead_grace: float = 1.0,
                 alive: Callable[[str], bool] = process_alive) -> None:
        self.max_lead_ns = max_lead_ns
        self.timeout = timeout
        self.dead_grace = min(dead_grace, timeout)
        self._alive = alive
        self._live: dict[str, _Participant] = {}
        self._expected = frozenset(expected)
        self.startup_timeout = startup_timeout
        #: expected role not heard (yet, or again after its process died) -> wall s since when
        self._missing = dict.fromkeys(self._expected, wall_now)
        self._suspended_at: float | None = None
        self._dropped: list[Dropped] = []

    @property
    def participants(self) -> dict[str, int]:
        """Live participant name -> last reported sim time (ns)."""
        return {name: p.reported_ns for name, p in self._live.items()}

    @property
    def waiting_for(self) -> frozenset[str]:
        """Expected roles not heard yet (empty once all have reported or the startup timeout gave up)."""
        return frozenset(self._missing)

    def report(self, name: str, time_ns: int, wall_now: float) -> bool:
        """Take one report; a ``time_ns`` of LEAVE_NS removes the participant.

        Returns:
            True when ``name`` joins: its first report, or its first since it was dropped or left.
        """
        if time_ns == LEAVE_NS:
            self._live.pop(name, None)
            return False
        self._missing.pop(role_of(name), None)
        known = self._live.get(name)
        if known is None:
            self._live[name] = _Participant(time_ns, wall_now)
            return True
        known.reported_ns = max(known.reported_ns, time_ns)  # a late, reordered report never moves back
        known.heard_wall = wall_now
        return False

    def limit_ns(self, wall_now: float) -> int | None:
        """The newest sim time (ns) the sim may reach now; None when nobody holds it back.

        HOLD while expected roles are missing. Drops the participants silent for ``timeout`` and
        gives up on missing roles after the startup timeout first (see :meth:`take_dropped`).
        """
        self._expire(wall_now)
        if self._missing:
            return HOLD
        if not self._live:
            return None
        return min(p.reported_ns for p in self._live.values()) + self.max_lead_ns

    def take_dropped(self) -> list[Dropped]:
        """The participants and roles given up on since the last call (each is returned once)."""
        dropped, self._dropped = self._dropped, []
        return dropped

    def suspend(self, wall_now: float) -> None:
        """Stop counting silence (the sim is paused: nobody owes a report)."""
        if self._suspended_at is None:
            self._suspended_at = wall_now

    def resume(self, wall_now: float) -> None:
        """Count silence again; the time spent suspended counts against nobody."""
        if self._suspended_at is None:
            return
        paused = wall_now - self._suspended_at
        self._suspended_at = None
        for participant in self._live.values():
            participant.heard_wall += paused
        for role in self._missing:
            self._missing[role] += paused

    def _expire(self, wall_now: float) -> None:
        if self._suspended_at is not None:
            return
        for name, p in list(self._live.items()):
            silent = wall_now - p.heard_wall
            if silent < self.dead_grace:
                continue
            gone = not self._alive(name)
            if gone or silent >= self.timeout:
                del self._live[name]
                role = role_of(name)
                awaited = gone and role in self._expected and all(role_of(n) != role for n in self._live)
                if awaited:
                    self._missing[role] = wall_now
                self._dropped.append(Dropped(role, name, silent, gone, awaited))
        for role, since in sorted(self._missing.items()):
            if wall_now - since >= self.startup_timeout:
                del self._missing[role]
                self._dropped.append(Dropped(role, None, wall_now - since))
