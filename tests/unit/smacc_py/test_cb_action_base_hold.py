"""CbNav2ZActionBase holds lockstep sim time while its action server is not discovered yet.

Why it matters: discovery takes wall time, and at ``--rtf max`` a simulator that went on meanwhile
would send the goal after a different amount of sim time on every run. The hold keeps sim time
still until the server is there (or the behavior gave up), so the goal leaves at the sim time the
state was entered. Stand-ins: the ROS context only records holds; the client hands out one
action whose discovery the test switches on.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import pytest

from smacc_py.clients.cl_nav2z import cb_action_base
from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.ros.context import DISCOVERY_HOLD_S, attach_ros_context


class RecordingContext:
    """Stands in for RosContext: keeps each lockstep hold (until, grace in wall s)."""

    def __init__(self) -> None:
        self.holds: list[tuple[Callable[[], bool], float]] = []

    def hold_lockstep(self, until: Callable[[], bool], grace_s: float) -> None:
        self.holds.append((until, grace_s))


class StandInAction:
    """An action client whose server is discovered when the test says so."""

    action_name = "navigate_to_pose"

    def __init__(self, discovered: bool) -> None:
        self.discovered = discovered

    def server_ready(self) -> bool:
        return self.discovered


class StandInClient:
    """ClNav2Z's part the behavior uses: its action clients and send_goal (recorded)."""

    def __init__(self, action: StandInAction) -> None:
        self.action = action
        self.sent: list[tuple[str, Any]] = []

    def action_client(self, key: str) -> StandInAction:
        return self.action

    def send_goal(self, key: str, goal: Any, on_done: Any = None) -> str:
        self.sent.append((key, goal))
        return "ticket"


class StandInMachine:
    """The machine clock (s, set by the test) and the failures posted to it."""

    def __init__(self) -> None:
        self.clock_s = 5.0
        self.failures: list[dict[str, Any]] = []

    def now(self) -> float:
        return self.clock_s


class CbGoTo(CbNav2ZActionBase):
    """Sends the goal "here" on navigate_to_pose."""

    server_wait_s = 10.0

    def make_goal(self) -> tuple[str, Any]:
        return "navigate_to_pose", "here"

    def post_failure_event(self, **payload: Any) -> None:  # the machine's event queue, recorded
        self.sm.failures.append(payload)  # type: ignore[attr-defined]


def entered(discovered: bool) -> tuple[CbGoTo, StandInClient, RecordingContext]:
    """A CbGoTo entered on a stand-in machine in lockstep; its server discovered or not."""
    machine, context = StandInMachine(), RecordingContext()
    attach_ros_context(machine, context)  # type: ignore[arg-type]
    client = StandInClient(StandInAction(discovered))
    behavior = CbGoTo()
    behavior.sm = machine  # type: ignore[assignment]
    behavior.requires_client = lambda _type: client  # type: ignore[assignment,method-assign,return-value]
    behavior.on_entry()
    return behavior, client, context


def test_a_discovered_server_gets_the_goal_at_once_and_nothing_is_held() -> None:
    _, client, context = entered(discovered=True)
    assert client.sent == [("navigate_to_pose", "here")]
    assert context.holds == []


def test_sim_time_is_held_until_the_server_is_discovered_then_the_goal_leaves() -> None:
    behavior, client, context = entered(discovered=False)
    assert client.sent == []
    [(released, grace_s)] = context.holds
    assert grace_s == DISCOVERY_HOLD_S
    assert not released()
    behavior.update()  # polled while waiting: still nothing to send
    assert client.sent == [] and not released()
    client.action.discovered = True
    assert released()
    behavior.update()
    assert client.sent == [("navigate_to_pose", "here")]


def test_the_hold_ends_when_the_behavior_gives_up_on_the_server(monkeypatch: pytest.MonkeyPatch) -> None:
    behavior, client, context = entered(discovered=False)
    [(released, _)] = context.holds
    later = time.monotonic() + behavior.server_wait_s + 1.0  # wall s: the wait is over on both clocks
    monkeypatch.setattr(cb_action_base, "time", SimpleNamespace(monotonic=lambda: later))
    behavior.sm.clock_s += behavior.server_wait_s + 1.0  # type: ignore[attr-defined]
    behavior.update()
    assert released()
    assert client.sent == []
    [failure] = behavior.sm.failures  # type: ignore[attr-defined]
    assert "'navigate_to_pose' not available after 10 s" in failure["reason"]
