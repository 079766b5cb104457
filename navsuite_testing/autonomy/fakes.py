"""Pure fakes for the autonomy node's seed nodes: a scripted NavigateToPose and a stepping clock.

``FakeNavigator`` implements the ``Navigator`` protocol of nav_stack.ros.autonomy.seed_nodes: each
goal pops the next scripted outcome ("succeeded", "aborted", "rejected", or "hold": run until
cancelled) and completes after ``travel_ticks`` polls, so GoToPose really is RUNNING for a while.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass, field

from nav_stack.ros.autonomy.locations import Location
from nav_stack.ros.autonomy.seed_nodes import NavOutcome

_OUTCOMES = {"succeeded": NavOutcome.SUCCEEDED, "aborted": NavOutcome.ABORTED,
             "rejected": NavOutcome.REJECTED}


@dataclass
class FakeGoal:
    location: Location
    script: str
    polls_left: int
    cancelled: bool = False
    _outcome: NavOutcome | None = None

    def outcome(self) -> NavOutcome | None:
        if self._outcome is None and self.script == "rejected":
            self._outcome = NavOutcome.REJECTED
        if self._outcome is None and self.script != "hold":
            self.polls_left -= 1
            if self.polls_left <= 0:
                self._outcome = _OUTCOMES[self.script]
        return self._outcome

    def detail(self) -> str:
        return "error_code 204: scripted" if self._outcome is NavOutcome.ABORTED else ""

    def cancel(self) -> None:
        if self._outcome is None:
            self.cancelled = True
            self._outcome = NavOutcome.CANCELED


@dataclass
class FakeNavigator:
    scripts: Iterable[str] = ()
    travel_ticks: int = 3
    ready: bool = True
    action_name: str = "navigate_to_pose"
    goals: list[FakeGoal] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._script = deque(self.scripts)

    def server_ready(self) -> bool:
        return self.ready

    def send(self, location: Location) -> FakeGoal:
        goal = FakeGoal(location, self._script.popleft() if self._script else "succeeded", self.travel_ticks)
        self.goals.append(goal)
        return goal


class StepClock:
    """A wall clock the test advances by hand (s)."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


class ListLog:
    """Collects log lines as ``LEVEL message``."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def info(self, message: str) -> None:
        self.lines.append(f"INFO {message}")

    def warning(self, message: str) -> None:
        self.lines.append(f"WARN {message}")

    def error(self, message: str) -> None:
        self.lines.append(f"ERROR {message}")
