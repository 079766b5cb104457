"""LockstepGate: the sim's limit from its participants' reports, leaving, timeouts, expected roles."""

from __future__ import annotations

import os
import subprocess
import sys

from sim2d.core.lockstep import HOLD, LEAVE_NS, Dropped, LockstepGate, process_alive, role_of

MS = 1_000_000        # ns
LEAD = 50 * MS        # ns: one 20 Hz control period


def _gate(expected: tuple[str, ...] = (), wall: float = 100.0) -> LockstepGate:
    return LockstepGate(LEAD, timeout=5.0, wall_now=wall, expected=expected, startup_timeout=60.0,
                        alive=lambda name: True)


def test_a_participant_whose_process_is_gone_is_dropped_after_the_grace_not_the_timeout() -> None:
    """A crash must not stall the world for the whole timeout, and a live process starved by a
    busy machine must not be given up on after a second: the pid in the name tells them apart."""
    gone = {"planner:9"}
    gate = LockstepGate(LEAD, timeout=30.0, wall_now=100.0, dead_grace=1.0,
                        alive=lambda name: name not in gone)
    gate.report("planner:9", 100 * MS, 100.0)
    gate.report("nav2:1", 50 * MS, 100.0)
    assert gate.limit_ns(100.9) == 50 * MS + LEAD
    assert gate.take_dropped() == []
    gate.report("nav2:1", 400 * MS, 101.0)
    assert gate.limit_ns(101.0) == 400 * MS + LEAD                 # 1.0 s silent, process gone: dropped now
    assert gate.take_dropped() == [Dropped("planner", "planner:9", 1.0, gone=True)]
    assert gate.limit_ns(130.9) == 400 * MS + LEAD                 # nav2 silent 29.9 s, alive: waited for
    assert gate.take_dropped() == []
    gate.limit_ns(131.0)
    assert gate.take_dropped() == [Dropped("nav2", "nav2:1", 30.0)]


def test_process_alive_checks_the_pid_in_the_name() -> None:
    finished = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                              text=True, check=True)
    assert process_alive(f"nav2:{os.getpid()}")
    assert not process_alive(f"nav2:{finished.stdout.strip()}")   # exited and reaped
    assert process_alive("a_node_without_pid")                     # nothing to check: the timeout decides


def test_no_participant_means_no_limit() -> None:
    gate = _gate()
    assert gate.limit_ns(100.0) is None
    assert gate.take_dropped() == []


def test_limit_is_the_slowest_report_plus_the_lead() -> None:
    gate = _gate()
    assert gate.report("nav2:1", 200 * MS, 100.0) is True          # joins
    assert gate.report("localization:2", 120 * MS, 100.0) is True
    assert gate.limit_ns(100.0) == 120 * MS + LEAD
    assert gate.report("localization:2", 240 * MS, 100.1) is False  # already live
    assert gate.limit_ns(100.1) == 200 * MS + LEAD
    gate.report("nav2:1", 150 * MS, 100.2)                         # reordered, older: never moves back
    assert gate.participants == {"nav2:1": 200 * MS, "localization:2": 240 * MS}


def test_leaving_releases_the_sim() -> None:
    gate = _gate()
    gate.report("nav2:1", 100 * MS, 100.0)
    gate.report("slow:2", 20 * MS, 100.0)
    assert gate.limit_ns(100.0) == 20 * MS + LEAD
    assert gate.report("slow:2", LEAVE_NS, 100.1) is False
    assert gate.limit_ns(100.1) == 100 * MS + LEAD
    gate.report("nav2:1", LEAVE_NS, 100.2)
    assert gate.limit_ns(100.2) is None
    assert gate.take_dropped() == []                               # leaving is not a fault


def test_a_silent_participant_is_dropped_once_and_rejoins_when_it_reports() -> None:
    gate = _gate()
    gate.report("nav2:1", 100 * MS, 100.0)
    gate.report("bt:2", 10 * MS, 100.0)
    gate.report("nav2:1", 300 * MS, 104.0)
    assert gate.limit_ns(104.9) == 10 * MS + LEAD                  # bt silent 4.9 s: still waited for
    assert gate.take_dropped() == []
    assert gate.limit_ns(105.0) == 300 * MS + LEAD                 # 5.0 s: dropped
    assert gate.take_dropped() == [Dropped("bt", "bt:2", 5.0)]
    assert gate.limit_ns(106.0) == 300 * MS + LEAD
    assert gate.take_dropped() == []                               # named once only
    assert gate.report("bt:2", 400 * MS, 107.0) is True            # back: it holds the sim again
    assert gate.limit_ns(107.0) == 300 * MS + LEAD
    gate.report("nav2:1", 500 * MS, 107.0)
    assert gate.limit_ns(107.0) == 400 * MS + LEAD


def test_expected_roles_hold_the_first_step_until_each_has_reported() -> None:
    gate = _gate(expected=("nav2", "localization"))
    assert gate.waiting_for == {"nav2", "localization"}
    assert gate.limit_ns(100.0) == HOLD
    gate.report("nav2:1", 1, 101.0)
    assert gate.limit_ns(101.0) == HOLD
    assert gate.waiting_for == {"localization"}
    gate.report("localization:7", 1, 102.0)
    assert gate.waiting_for == frozenset()
    assert gate.limit_ns(102.0) == 1 + LEAD


def test_missing_expected_roles_are_named_once_after_the_startup_timeout() -> None:
    gate = _gate(expected=("nav2", "localization"))
    gate.report("nav2:1", 1, 110.0)
    gate.report("nav2:1", 1, 158.0)               # answers the repeated /clock while the sim holds
    assert gate.limit_ns(159.9) == HOLD
    assert gate.limit_ns(160.0) == 1 + LEAD       # nav2 is still live: its report holds the sim
    assert gate.take_dropped() == [Dropped("localization", None, 60.0)]
    assert gate.take_dropped() == []
    assert gate.waiting_for == frozenset()


def test_silence_while_suspended_counts_against_nobody() -> None:
    gate = _gate(expected=("late",))
    gate.report("nav2:1", 100 * MS, 100.0)
    gate.suspend(101.0)
    assert gate.limit_ns(150.0) == HOLD            # nothing expires while suspended
    gate.resume(151.0)                             # 50 s suspended
    assert gate.limit_ns(154.9) == HOLD            # nav2 silent 4.9 s of counted time
    assert gate.take_dropped() == []
    assert gate.limit_ns(155.0) == HOLD
    assert gate.take_dropped() == [Dropped("nav2", "nav2:1", 5.0)]
    assert gate.limit_ns(209.9) == HOLD            # the startup deadline moved by the 50 s too
    assert gate.limit_ns(210.0) is None
    assert gate.take_dropped() == [Dropped("late", None, 60.0)]


def test_role_is_the_name_before_the_last_colon() -> None:
    assert role_of("nav2:4242") == "nav2"
    assert role_of("ns:sub:17") == "ns:sub"
    assert role_of("plain") == "plain"


def test_an_expected_role_whose_process_is_gone_is_awaited_again_until_a_respawn_joins() -> None:
    """A respawned stack starts under a new pid: the world must not run on while it starts; a role
    that never comes back is given up after the startup timeout, as at the start; a participant
    whose role was not expected is not waited for."""
    gone: set[str] = set()
    gate = LockstepGate(LEAD, timeout=30.0, wall_now=100.0, expected=("nav2",), startup_timeout=60.0,
                        dead_grace=1.0, alive=lambda name: name not in gone)
    gate.report("nav2:7", 300 * MS, 100.0)
    gate.report("probe:3", 900 * MS, 100.0)
    assert gate.limit_ns(100.0) == 300 * MS + LEAD
    gone.update({"nav2:7", "probe:3"})
    assert gate.limit_ns(101.0) == HOLD                      # both silent 1 s and gone: nav2 held for
    assert gate.take_dropped() == [Dropped("nav2", "nav2:7", 1.0, gone=True, awaited=True),
                                   Dropped("probe", "probe:3", 1.0, gone=True)]
    assert gate.waiting_for == {"nav2"}
    assert gate.report("nav2:8", 310 * MS, 104.0) is True     # the respawned process joins
    assert gate.waiting_for == frozenset()
    assert gate.limit_ns(104.0) == 310 * MS + LEAD
    gone.add("nav2:8")                                        # dies too, and nothing restarts it
    assert gate.limit_ns(105.0) == HOLD
    assert gate.take_dropped() == [Dropped("nav2", "nav2:8", 1.0, gone=True, awaited=True)]
    assert gate.limit_ns(164.9) == HOLD                       # 59.9 s after it was found gone
    assert gate.limit_ns(165.0) is None                       # given up: nobody holds the sim
    assert gate.take_dropped() == [Dropped("nav2", None, 60.0)]
