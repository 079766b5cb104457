"""GoalTicket.waiting_for, pending_goals: a machine that times out in a state says what its goal waits for."""

from __future__ import annotations

import pytest

pytest.importorskip("action_msgs.msg")

from smacc_py.ros.action_client import _SENT, GoalOutcome, GoalTicket, pending_goals


def test_each_stage_of_a_goal_names_what_it_waits_for() -> None:
    ticket = GoalTicket("/navigate_to_pose", goal=None)
    ticket.sent_at = 100.0
    assert ticket.waiting_for(now=112.0) == "navigate_to_pose goal: sent 12.0 s ago, not accepted yet"
    ticket.accepted_at = 100.5
    assert ticket.waiting_for(now=112.0) == "navigate_to_pose goal: accepted 11.5 s ago, no feedback yet"
    ticket.feedbacks, ticket.last_feedback_at = 3, 111.9
    expected = "navigate_to_pose goal: accepted 11.5 s ago, 3 feedback messages, the last 0.1 s ago"
    assert ticket.waiting_for(now=112.0) == expected
    ticket.finish(GoalOutcome.SUCCEEDED, None)
    assert ticket.waiting_for(now=112.0) == "navigate_to_pose goal: succeeded"


def test_pending_goals_lists_the_open_goals_oldest_first_and_forgets_ended_and_abandoned_ones() -> None:
    older, newer, ended, abandoned = (GoalTicket(name, goal=None) for name in ("a", "b", "c", "d"))
    older.sent_at, newer.sent_at = 1.0, 2.0
    for ticket in (newer, older, ended, abandoned):
        _SENT.add(ticket)
    ended.finish(GoalOutcome.ABORTED, None)
    abandoned.abandoned = True
    mine = [line for line in pending_goals() if line.split(" ", 1)[0] in {"a", "b", "c", "d"}]
    assert [line.split(" ", 1)[0] for line in mine] == ["a", "b"]
