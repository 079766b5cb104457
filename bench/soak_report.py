"""The soak benchmark's plan (which worlds, robots and goal counts) and its results: summary and rows.

Pure: no ROS. bench_soak fills a ConfigResult per configuration as its goals end; this module
classifies the failures, prints the summary tables and queues the RESULTS.md rows.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass, field

from bench.harness import Benchmark
from bench.nav_session import REPO, GoalRecord
from bench.proc_memory import MemoryGrowth, largest_growth

WORLDS = REPO / "sim2d" / "worlds"


@dataclass(frozen=True)
class Config:
    """One stack of the soak: a sim2d world, a robot model and how many goals it drives."""

    world: str
    robot: str
    goals: int

    @property
    def label(self) -> str:
        return f"{self.world}/{self.robot}"

    def __str__(self) -> str:
        return f"{self.world}:{self.robot}:{self.goals}"


def parse_plan(text: str) -> list[Config]:
    """``world:robot:goals,...`` -> Configs; a ValueError names the item that is wrong and why."""
    from nav_stack.ros.bringup.robot_params import ROBOTS

    configs = []
    for item in (part.strip() for part in text.split(",")):
        fields = item.split(":")
        if len(fields) != 3:
            raise ValueError(f"--plan: {item!r} is not world:robot:goals")
        world, robot, goals = fields
        if not (WORLDS / f"{world}.yaml").is_file() or not (REPO / "maps" / f"{world}.yaml").is_file():
            raise ValueError(f"--plan: {item!r}: no world {world!r} with a map (sim2d/worlds/{world}.yaml "
                             f"and maps/{world}.yaml)")
        if robot not in ROBOTS:
            raise ValueError(f"--plan: {item!r}: unknown robot {robot!r} (known: {', '.join(ROBOTS)})")
        if not goals.isdigit() or int(goals) < 1:
            raise ValueError(f"--plan: {item!r}: goals must be a positive integer, got {goals!r}")
        configs.append(Config(world, robot, int(goals)))
    return configs


def split_goals(total: int, parts: int) -> list[int]:
    """``total`` goals over ``parts`` configurations, as evenly as possible (the first ones get the rest)."""
    if total < 1 or parts < 1:
        raise ValueError(f"--goals must be positive, got {total}")
    share, rest = divmod(total, parts)
    return [share + (1 if index < rest else 0) for index in range(parts)]


@dataclass
class ConfigResult:
    """What one configuration's stack did. ``error`` says why it ended before its last goal."""

    config: Config
    records: list[GoalRecord] = field(default_factory=list)
    collisions: int = 0
    memory: list[MemoryGrowth] = field(default_factory=list)
    battery: float | None = None  # charge at the end, 0..1
    error: str | None = None

    @property
    def missing(self) -> int:
        """Goals never driven because the configuration failed (not when it was interrupted)."""
        return self.config.goals - len(self.records) if self.error is not None else 0

    @property
    def goals(self) -> int:
        return len(self.records) + self.missing

    @property
    def successes(self) -> int:
        return sum(record.outcome.ok for record in self.records)

    @property
    def explained(self) -> int:
        return sum(record.outcome.explained for record in self.records)

    @property
    def unexplained(self) -> int:
        return self.goals - self.successes - self.explained


def _fmt(value: float | None, spec: str, unit: str = "") -> str:
    return "n/a" if value is None else f"{value:{spec}}{unit}"


def _median(values: list[float]) -> float | None:
    return statistics.median(values) if values else None


@dataclass(frozen=True)
class Tally:
    """The counts of one or more configurations (the total sums them)."""

    goals: int
    successes: int
    collisions: int
    explained: int
    unexplained: int
    battery: float | None  # %, the lowest charge at the end
    records: tuple[GoalRecord, ...]

    @classmethod
    def of(cls, results: list[ConfigResult]) -> Tally:
        charges = [100.0 * result.battery for result in results if result.battery is not None]
        return cls(sum(r.goals for r in results), sum(r.successes for r in results),
                   sum(r.collisions for r in results), sum(r.explained for r in results),
                   sum(r.unexplained for r in results), min(charges) if charges else None,
                   tuple(record for result in results for record in result.records))

    @property
    def success_rate(self) -> float:
        """% of the goals (those never driven after an early end included)."""
        return 100.0 * self.successes / self.goals if self.goals else 0.0

    @property
    def ratio_median(self) -> float | None:
        """Median time-to-goal over the ideal time, of the goals reached."""
        return _median([record.ratio for record in self.records if record.outcome.ok])

    @property
    def wall_median(self) -> float | None:
        """Median wall seconds per goal (goals that were accepted)."""
        return _median([record.wall_s for record in self.records if record.wall_s > 0.0])


def print_summary(results: list[ConfigResult]) -> None:
    """The per-configuration and total table, the memory table and every failure's message."""
    print("\nsoak summary", flush=True)
    print(f"{'configuration':26} {'goals':>5} {'ok':>4} {'success':>8} {'collisions':>10} {'explained':>9} "
          f"{'unexplained':>11} {'battery':>8} {'ratio med':>9} {'wall/goal':>9}")
    for label, t in [*((r.config.label, Tally.of([r])) for r in results), ("total", Tally.of(results))]:
        print(f"{label:26} {t.goals:5d} {t.successes:4d} {t.success_rate:7.1f}% {t.collisions:10d} "
              f"{t.explained:9d} {t.unexplained:11d} {_fmt(t.battery, '7.1f', '%'):>8} "
              f"{_fmt(t.ratio_median, '8.2f', 'x'):>9} {_fmt(t.wall_median, '7.1f', ' s'):>9}")
    print(f"\n{'configuration':26} {'process (RSS, MiB)':28} {'warm':>8} {'end':>8} {'growth':>8}")
    for result in results:
        for growth in result.memory:
            print(f"{result.config.label:26} {growth.name:28} {_fmt(growth.warm, '8.1f'):>8} "
                  f"{_fmt(growth.end, '8.1f'):>8} {_fmt(growth.percent, '+7.1f', '%'):>8}")
    for result in results:
        for record in result.records:
            if not record.outcome.ok:
                kind = "explained" if record.outcome.explained else "UNEXPLAINED"
                print(f"failure {result.config.label} goal {record.index}: {kind} (error_code "
                      f"{record.outcome.code}): {record.outcome.message or '(no error_msg)'}")
        if result.error is not None:
            print(f"failure {result.config.label}: ended early, {result.missing} goals not driven: "
                  f"{result.error}")
    print(flush=True)


def _memory_note(growths: list[MemoryGrowth]) -> str:
    return ", ".join(f"{g.name} {_fmt(g.warm, '.1f')} -> {_fmt(g.end, '.1f')} MiB "
                     f"({_fmt(g.percent, '+.1f', ' %')})" for g in growths)


def record(bench: Benchmark, results: list[ConfigResult], note: str) -> None:
    """Queue the rows: per configuration, then the totals."""
    for result in results:
        label, tally = result.config.label, Tally.of([result])
        config_note = f"{len(result.records)}/{result.config.goals} goals, {note}"
        if result.error is not None:
            config_note += f"; ended early: {result.error}"
        bench.record_value(f"success rate ({label})", tally.success_rate, "%", config_note)
        bench.record_value(f"collisions ({label})", float(tally.collisions), "count", config_note)
        bench.record_value(f"unexplained failures ({label})", float(tally.unexplained), "count",
                           f"{config_note}; explained failures {tally.explained}")
        if tally.battery is not None:
            bench.record_value(f"battery at end ({label})", tally.battery, "%", config_note)
        largest = largest_growth(result.memory)
        if largest is not None and largest.percent is not None:
            bench.record_value(f"largest RSS growth ({label})", largest.percent, "%",
                               f"{config_note}; warm -> end: "
                               f"{_memory_note(result.memory)}")
    total = Tally.of(results)
    note = f"{total.goals} goals over {', '.join(str(result.config) for result in results)}, {note}"
    bench.record_value("success rate (total)", total.success_rate, "%", note)
    for metric, count in (("collisions", total.collisions), ("explained failures", total.explained),
                          ("unexplained failures", total.unexplained)):
        bench.record_value(f"{metric} (total)", float(count), "count", note)
    if total.battery is not None:
        bench.record_value("lowest battery at end", total.battery, "%", note)
    largest = largest_growth([MemoryGrowth(f"{growth.name} in {result.config.label}", growth.warm, growth.end)
                              for result in results for growth in result.memory])
    if largest is not None and largest.percent is not None:
        bench.record_value("largest RSS growth (total)", largest.percent, "%",
                           f"{note}; {_memory_note([largest])}")
    if total.ratio_median is not None:
        bench.record_value("time-to-goal / ideal (median)", total.ratio_median, "x", note)
    if total.wall_median is not None:
        bench.record_value("wall time per goal (median)", total.wall_median, "s", note)
