"""bench.dock_patrol_tally: what the 4 h docking patrol counts as a round, a docking, a hanging goal and a
missed docking, from the values its topics carry."""

from __future__ import annotations

from bench.dock_patrol_tally import DOCK_GRACE, PatrolTally, progress_line

ACCEPTED, EXECUTING, SUCCEEDED, CANCELED, ABORTED = 1, 2, 4, 5, 6
A, B, C = b"a" * 16, b"b" * 16, b"c" * 16


def test_each_goal_counts_once_with_its_first_final_status() -> None:
    tally = PatrolTally(0.2)
    tally.on_statuses("navigate_to_pose", [(A, ACCEPTED)], 1.0)
    tally.on_statuses("navigate_to_pose", [(A, EXECUTING), (B, ACCEPTED)], 2.0)
    tally.on_statuses("navigate_to_pose", [(A, SUCCEEDED), (B, ABORTED)], 3.0)
    tally.on_statuses("navigate_to_pose", [(A, SUCCEEDED), (B, ABORTED), (C, CANCELED)], 4.0)
    tally.on_statuses("navigate_to_pose", [(C, CANCELED)], 14.0)  # A and B expired on the server
    totals = tally.totals()
    assert (totals["sent"], totals["succeeded"], totals["failed"], totals["canceled"]) == (3, 1, 1, 1)
    assert totals["hanging"] == 0 and totals["unseen"] == 0
    assert tally.failures(14.0) == []


def test_a_goal_still_listed_without_a_result_hangs_and_fails_the_run() -> None:
    tally = PatrolTally(0.2)
    tally.on_statuses("dock_robot", [(A, EXECUTING)], 1.0)
    tally.on_statuses("undock_robot", [(B, EXECUTING)], 1.0)
    tally.on_statuses("undock_robot", [(B, SUCCEEDED)], 2.0)
    assert tally.totals()["hanging"] == 1
    assert tally.failures(2.0) == ["1 goal(s) left hanging"]


def test_a_goal_dropped_before_its_end_was_seen_is_counted_apart_not_as_hanging() -> None:
    tally = PatrolTally(0.2)
    tally.on_statuses("navigate_to_pose", [(A, EXECUTING)], 1.0)
    tally.on_statuses("navigate_to_pose", [], 12.0)
    assert (tally.totals()["hanging"], tally.totals()["unseen"]) == (0, 1)


def test_a_round_is_the_last_legs_success() -> None:
    tally = PatrolTally(0.2)
    for leaf in ("go_to_location1", "go_to_location4", "dock_robot"):
        tally.on_tree_event(leaf, "RUNNING")
        tally.on_tree_event(leaf, "SUCCESS")
    tally.on_tree_event("go_to_location4", "FAILURE")
    assert tally.rounds == 1


def test_a_low_battery_episode_ends_with_a_successful_docking() -> None:
    tally = PatrolTally(0.2)
    tally.on_battery(0.5, False, 10.0)
    tally.on_battery(0.2, False, 100.0)  # opens it
    tally.on_battery(0.19, False, 101.0)  # the same episode
    tally.on_statuses("dock_robot", [(A, EXECUTING)], 110.0)
    tally.on_battery(0.19, True, 130.0)
    tally.on_statuses("dock_robot", [(A, SUCCEEDED)], 130.5)
    tally.on_battery(0.25, True, 300.0)
    assert tally.episode_counts(5000.0) == (1, 0, 0)
    assert (tally.dockings(), tally.charging_starts, tally.lowest_charge) == (1, 1, 0.19)


def test_an_episode_left_open_is_pending_near_the_end_and_missed_before() -> None:
    tally = PatrolTally(0.2)
    tally.on_statuses("dock_robot", [(A, ABORTED)], 50.0)  # a failed docking does not close it
    tally.on_battery(0.18, False, 40.0)
    tally.on_statuses("dock_robot", [(A, ABORTED), (B, ABORTED)], 60.0)
    assert tally.episode_counts(40.0 + DOCK_GRACE - 1.0) == (0, 1, 0)
    assert tally.episode_counts(40.0 + DOCK_GRACE + 1.0) == (0, 0, 1)
    assert tally.failures(40.0 + DOCK_GRACE + 1.0) == ["1 low-battery episode(s) without a docking"]


def test_collisions_fail_the_run_with_where_they_were() -> None:
    tally = PatrolTally(0.2)
    tally.collisions.append((12.0, -0.55, -2.2))
    assert tally.failures(20.0) == ["1 collision(s) at (-0.55, -2.20) sim 12 s"]


def test_the_progress_line_is_one_line_with_the_counts() -> None:
    tally = PatrolTally(0.2)
    tally.on_battery(0.9, False, 1.0)
    tally.on_statuses("navigate_to_pose", [(A, SUCCEEDED)], 2.0)
    line = progress_line(tally, 600.0, 120.0)
    assert "\n" not in line
    assert "sim  0.17 h" in line and "rtf  5.0" in line and "charge  90.0 %" in line
    assert "goals 1 sent / 1 ok / 0 failed" in line
