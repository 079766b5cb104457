"""The docking patrol's tally (bench/bench_dock_patrol.py): pure, fed with plain values from its topics.

Why apart: what counts as a round, a hanging goal or a missed docking is the bench's verdict, and it is
tested without ROS (tests/unit/bench/test_dock_patrol_tally.py). Times are the simulator's (sim s),
charges fractions of a full battery.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

ACTIONS = ("navigate_to_pose", "dock_robot", "undock_robot")
ROUND_LEAF = "go_to_location4"  # the last leg of a round in the docking tree
# action_msgs/GoalStatus: 1-3 are in flight, 4-6 final.
SUCCEEDED, CANCELED, ABORTED = 4, 5, 6
DOCK_GRACE = 300.0  # sim s: a leg (under 60 s) and a docking (about 20 s) with retries


@dataclass
class GoalTally:
    """The goals of one action, from its ``_action/status`` arrays (goal id -> last status seen)."""

    last: dict[bytes, int] = field(default_factory=dict)
    listed: set[bytes] = field(default_factory=set)  # ids in the newest array

    def update(self, statuses: Iterable[tuple[bytes, int]]) -> list[bytes]:
        """Take one status array; return the goals that succeeded with it."""
        succeeded, listed = [], set()
        for goal, status in statuses:
            listed.add(goal)
            before = self.last.get(goal, 0)
            if before < SUCCEEDED:  # the first final status is the goal's outcome
                self.last[goal] = status
                succeeded += [goal] if status == SUCCEEDED else []
        self.listed = listed
        return succeeded

    def count(self, status: int) -> int:
        return sum(1 for last in self.last.values() if last == status)

    @property
    def in_flight(self) -> int:
        """Still listed with no final status: hanging once the run has ended."""
        return sum(1 for goal in self.listed if self.last[goal] < SUCCEEDED)

    @property
    def unseen_end(self) -> int:
        """Dropped from the array (a server forgets a goal only after its end) before its end was seen."""
        return sum(1 for goal, last in self.last.items() if last < SUCCEEDED and goal not in self.listed)


@dataclass
class Episode:
    """A low-battery episode: from the first charge at or below the threshold (sim s) to the docking."""

    start: float
    docked_at: float | None = None


@dataclass
class PatrolTally:
    """Everything the bench counts, fed with plain values by the subscriptions (sim s, fractions)."""

    low_threshold: float
    goals: dict[str, GoalTally] = field(default_factory=lambda: {name: GoalTally() for name in ACTIONS})
    rounds: int = 0
    charging_starts: int = 0
    lowest_charge: float = 1.0
    charge: float = float("nan")
    collisions: list[tuple[float, float, float]] = field(default_factory=list)  # sim s, x m, y m
    episodes: list[Episode] = field(default_factory=list)
    _charging: bool = False

    @property
    def open_episode(self) -> Episode | None:
        return self.episodes[-1] if self.episodes and self.episodes[-1].docked_at is None else None

    def on_statuses(self, action: str, statuses: Iterable[tuple[bytes, int]], now: float) -> None:
        docked = self.goals[action].update(statuses)
        episode = self.open_episode
        if action == "dock_robot" and docked and episode is not None:
            episode.docked_at = now

    def on_tree_event(self, node: str, current: str) -> None:
        if node == ROUND_LEAF and current == "SUCCESS":
            self.rounds += 1

    def on_battery(self, charge: float, charging: bool, now: float) -> None:
        self.charge = charge
        self.lowest_charge = min(self.lowest_charge, charge)
        self.charging_starts += int(charging and not self._charging)
        self._charging = charging
        if charge <= self.low_threshold and not charging and self.open_episode is None:
            self.episodes.append(Episode(now))

    def dockings(self) -> int:
        return self.goals["dock_robot"].count(SUCCEEDED)

    def episode_counts(self, end: float) -> tuple[int, int, int]:
        """(docked, pending, missed) low-battery episodes at sim time ``end``."""
        docked = sum(1 for episode in self.episodes if episode.docked_at is not None)
        open_ = [episode.start for episode in self.episodes if episode.docked_at is None]
        pending = sum(1 for start in open_ if end - start < DOCK_GRACE)
        return docked, pending, len(open_) - pending

    def totals(self) -> dict[str, int]:
        """Goals of the three actions together: sent, succeeded, failed (aborted), canceled, hanging."""
        tallies = self.goals.values()
        return {"sent": sum(len(t.last) for t in tallies),
                "succeeded": sum(t.count(SUCCEEDED) for t in tallies),
                "failed": sum(t.count(ABORTED) for t in tallies),
                "canceled": sum(t.count(CANCELED) for t in tallies),
                "hanging": sum(t.in_flight for t in tallies),
                "unseen": sum(t.unseen_end for t in tallies)}

    def failures(self, end: float) -> list[str]:
        """Why the run fails its bar (empty: it passes)."""
        reasons = []
        totals = self.totals()
        if totals["hanging"]:
            reasons.append(f"{totals['hanging']} goal(s) left hanging")
        if self.collisions:
            reasons.append(f"{len(self.collisions)} collision(s) at " + ", ".join(
                f"({x:.2f}, {y:.2f}) sim {t:.0f} s" for t, x, y in self.collisions[:5]))
        missed = self.episode_counts(end)[2]
        if missed:
            reasons.append(f"{missed} low-battery episode(s) without a docking")
        return reasons


def progress_line(tally: PatrolTally, sim_s: float, wall_s: float) -> str:
    """One calm line: where the run stands."""
    t = tally.totals()
    return (f"dock_patrol: sim {sim_s / 3600:5.2f} h, wall {wall_s / 60:5.1f} min "
            f"(rtf {sim_s / max(wall_s, 1e-9):4.1f}), "
            f"rounds {tally.rounds}, dockings {tally.dockings()}, charge {100 * tally.charge:5.1f} % "
            f"(lowest {100 * tally.lowest_charge:.1f}), goals {t['sent']} sent / {t['succeeded']} ok / "
            f"{t['failed']} failed, collisions {len(tally.collisions)}")
