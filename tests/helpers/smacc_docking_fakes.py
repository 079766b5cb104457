"""A scripted docking server for the cl_nav2z docking behaviors, on smacc_nav2z_more_fakes's world, and
an observer that keeps the events a machine posted.

``DockingNav2`` is a MoreNav2 whose ``dock_robot`` and ``undock_robot`` goals end as ``docking`` says:
each goal takes the next ``(outcome, error_code, error_msg, num_retries)`` of the script of its action
("succeeded", "aborted" or "hold" until cancelled); past the script a goal succeeds. Results are the real
nav2_msgs DockRobot/UndockRobot results (``success`` false on failure, as the server sets it).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable
from typing import Any

from smacc_py.clients.cl_nav2z.client import ACTION_TYPES, DOCK_ROBOT, UNDOCK_ROBOT
from smacc_py.core import SmaccEvent, SmaccObserver
from smacc_py.ros.action_client import GoalOutcome
from tests.helpers.smacc_fake_nav import Nav2Script
from tests.helpers.smacc_nav2z_more_fakes import MoreNav2

DOCKING_ACTIONS = {key: ACTION_TYPES[key] for key in (DOCK_ROBOT, UNDOCK_ROBOT)}
DockScript = tuple[str, int, str, int]  # outcome, error_code, error_msg, num_retries


class PostedEvents(SmaccObserver):
    """Every event posted to the machine; ``of(type)`` those of one type (payload attributes read freely)."""

    def __init__(self) -> None:
        self.events: list[SmaccEvent] = []

    def on_event_posted(self, sm: Any, event: SmaccEvent) -> None:
        self.events.append(event)

    def of(self, event_type: type[SmaccEvent]) -> list[Any]:
        return [e for e in self.events if isinstance(e, event_type)]


class DockingNav2(MoreNav2):
    """MoreNav2 with a scripted docking server (module docstring)."""

    def __init__(self, docking: dict[str, Iterable[DockScript]] | None = None,
                 script: Nav2Script | None = None) -> None:
        super().__init__(script)
        self._docking = {key: deque((docking or {}).get(key, ())) for key in (DOCK_ROBOT, UNDOCK_ROBOT)}
        self._pending: dict[int, DockScript] = {}

    def decide(self, key: str, goal: Any) -> str:
        if key not in DOCKING_ACTIONS:
            return super().decide(key, goal)
        scripted = self._docking[key].popleft() if self._docking[key] else ("succeeded", 0, "", 0)
        self._pending[id(goal)] = scripted
        return scripted[0]

    def result(self, key: str, goal: Any, outcome: GoalOutcome, decision: str = "") -> Any:
        if key not in DOCKING_ACTIONS:
            return super().result(key, goal, outcome, decision)
        _, code, message, retries = self._pending.pop(id(goal), ("succeeded", 0, "", 0))
        result = DOCKING_ACTIONS[key].Result()
        result.success = outcome is GoalOutcome.SUCCEEDED
        if outcome is GoalOutcome.ABORTED:
            result.error_code, result.error_msg = code, message
        if hasattr(result, "num_retries"):
            result.num_retries = retries
        return result
