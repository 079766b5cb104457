"""What one scenario run measured, and whether that passes its criteria. Pure (stdlib only).

The worker fills an ``Outcome`` (from the mission command's console lines and the run's recording) and
writes it as JSON; ``judge`` compares it with the scenario's ``Expect``. Every failing criterion is
kept, in the order of ``Expect``'s fields, so the table can name the first and the reports all of them.
A criterion whose quantity was not measured fails ("not measured"): a run without a recording must not
pass a localization bound by default.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields
from typing import Any

from navsuite_tools.scenarios.outcome import MissionFacts
from navsuite_tools.scenarios.schema import Expect


@dataclass(frozen=True)
class Outcome(MissionFacts):
    """One run's facts: the mission's own (:class:`MissionFacts`, from its console) and the farm's.
    ``result`` is SUCCESS, ABORT, TIMEOUT (the mission's own wall-clock limit or the farm's), STACK (the
    stack died or never came up) or ERROR (the runner itself failed: ``detail``).

    sim_time: s of sim time the mission took; wall_time: s of wall time the scenario took, bringup
    included; max_localization_error: m (AMCL against the truth); min_clearance: m, the smallest
    ground-truth gap between the robot's body and an obstacle; artifacts: name → path; attempts: how
    many times the scenario was started (2 when a cluster worker died under it and it was re-queued).
    """

    collisions: int | None = None
    max_localization_error: float | None = None
    min_clearance: float | None = None
    exit_code: int | None = None
    wall_time: float = 0.0
    events_applied: tuple[str, ...] = ()
    artifacts: dict[str, str] = field(default_factory=dict)
    attempts: int = 1

    def to_json(self) -> dict[str, Any]:
        data = asdict(self)
        data["events_applied"] = list(self.events_applied)
        return data

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Outcome:
        names = {f.name for f in fields(cls)}
        clean = {key: value for key, value in data.items() if key in names}
        clean["events_applied"] = tuple(clean.get("events_applied", ()))
        return cls(**clean)


@dataclass(frozen=True)
class Verdict:
    """``failures`` holds one ``"<criterion>: <why>"`` line per failing criterion, first one first."""

    passed: bool
    failures: tuple[str, ...] = ()

    @property
    def criterion(self) -> str:
        """The first failing criterion's name ('' when passed)."""
        return self.failures[0].split(":", 1)[0] if self.failures else ""

    def describe(self) -> str:
        return "passed" if self.passed else "; ".join(self.failures)


def judge(expect: Expect, outcome: Outcome, injected: int = 0) -> Verdict:
    """Every criterion of ``expect`` against ``outcome``; a runner error fails before any criterion.

    ``injected``: events the injector had to apply at sim times (farm.injected_events); fewer applied
    lines in the outcome fail the run (``events``), so a scenario never passes with its fault silently
    left out.
    """
    if outcome.result == "ERROR":
        return Verdict(False, (f"run: {outcome.detail or 'the runner failed'}",))
    failures: list[str] = []

    def equal(name: str, wanted: object, got: object) -> None:
        if wanted is not None and got != wanted:
            failures.append(f"{name}: expected {wanted}, got {'not measured' if got is None else got}")

    def at_most(name: str, bound: float | None, got: float | None, unit: str) -> None:
        if bound is None:
            return
        if got is None:
            failures.append(f"{name}: not measured (bound {bound:g}{unit})")
        elif got > bound:
            failures.append(f"{name}: {got:.3g}{unit} > {bound:g}{unit}")

    want_result = expect.result
    if want_result is not None and outcome.result != want_result:
        why = f" ({outcome.detail})" if outcome.detail else ""
        failures.append(f"result: expected {want_result}, got {outcome.result}{why}")
    equal("final_state", expect.final_state, outcome.final_state)
    equal("tag", expect.tag, outcome.tag)
    equal("result_code", expect.result_code, outcome.result_code)
    at_most("max_sim_time", expect.max_sim_time, outcome.sim_time, " s")
    at_most("max_collisions", expect.max_collisions, outcome.collisions, "")
    at_most("max_localization_error", expect.max_localization_error, outcome.max_localization_error, " m")
    if expect.min_clearance is not None:
        if outcome.min_clearance is None:
            failures.append(f"min_clearance: not measured (bound {expect.min_clearance:g} m)")
        elif outcome.min_clearance < expect.min_clearance:
            failures.append(f"min_clearance: {outcome.min_clearance:.3f} m < {expect.min_clearance:g} m")
    if len(outcome.events_applied) < injected:
        failures.append(f"events: {len(outcome.events_applied)} of {injected} applied")
    return Verdict(not failures, tuple(failures))
