"""Read a mission's result from the console lines of the command that ran it. Pure (re + stdlib).

The mission commands print stable lines that tests and benchmarks already parse; these are them:

* navsuite-demo / sm-battery-patrol (smacc_py.ros.transition_printer and the commands' summaries):
  ``[t=19.87 s] StA -> StB [SUCCESS] on EvX[...] (why)``, ``result: SUCCESS: ...`` / ``ABORT: ...`` /
  ``TIMEOUT ...`` / ``the stack stopped ...``, ``sim time 43.0 s`` (demo) or ``sim 123.4 s`` (patrol);
* the goal driver: ``goal 1: result: SUCCEEDED (error_code 0) in 12.30 s sim`` per goal, then
  ``goals: 1 of 2 reached; sim 12.70 s``;
* nav-autonomy: ``cycle 2: root SUCCESS in 31.0 s`` / ``cycle 1: root FAILURE at 'Leaf' in ...``.

When no result line was printed (the process was killed) the exit code decides (stack_run's codes).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass

TRANSITION = re.compile(r"\[t=(?P<t>[\d.]+) s\] (?P<source>\w+) -> (?P<target>\w+) \[(?P<tag>\w+)\]")
MACHINE_RESULT = re.compile(r"\] result: (?P<word>SUCCESS|ABORT|TIMEOUT|the stack stopped|interrupted)")
GOAL_RESULT = re.compile(r"^goal (?P<n>\d+): result: (?P<status>\w+(?: \d+)?) \(error_code (?P<code>\d+)\)")
GOALS_END = re.compile(r"^goals: (?P<reached>\d+) of (?P<total>\d+) reached; sim (?P<s>[\d.]+) s")
SIM_TIME = re.compile(r"\bsim(?: time)? (?P<s>[\d.]+) s\b")
ERROR_CODE = re.compile(r"error_code (?P<code>\d+)")
BT_CYCLE = re.compile(r"cycle (?P<n>\d+): root (?P<status>SUCCESS|FAILURE)(?: at '(?P<leaf>[^']*)')?")
#: stack_run's exit codes → result words, for a command that ended without its result line.
EXIT_RESULTS = {0: "SUCCESS", 1: "ABORT", 2: "TIMEOUT", 3: "STACK", 130: "TIMEOUT"}
_WORDS = {"the stack stopped": "STACK", "interrupted": "TIMEOUT"}


@dataclass(frozen=True)
class MissionFacts:
    """What the console said: result word, its line, last state and tag, Nav2 error code, sim s."""

    result: str
    detail: str = ""
    final_state: str | None = None
    tag: str | None = None
    result_code: int | None = None
    sim_time: float | None = None


def machine_facts(lines: Iterable[str], exit_code: int | None) -> MissionFacts:
    """A state-machine command's run (navsuite-demo, sm-battery-patrol)."""
    final_state = tag = detail = None
    result_code: int | None = None
    sim_time: float | None = None
    word: str | None = None
    for line in lines:
        if (transition := TRANSITION.search(line)) is not None:  # the last transition's code counts
            final_state, tag = transition["target"], transition["tag"]
            code = ERROR_CODE.search(line)
            result_code = int(code["code"]) if code is not None else None
        if (result := MACHINE_RESULT.search(line)) is not None:
            word = _WORDS.get(result["word"], result["word"])
            detail = line[result.start("word"):].strip()
        if (sim := SIM_TIME.search(line)) is not None and ("summary" in line or "transitions:" in line
                                                           or "rounds" in line):
            sim_time = float(sim["s"])
    if word is None:
        word = EXIT_RESULTS.get(exit_code if exit_code is not None else -1, "STACK")
        detail = f"no result line; exit code {exit_code}"
    if result_code is None and word == "SUCCESS":
        result_code = 0
    return MissionFacts(word, detail or "", final_state, tag, result_code, sim_time)


def goal_facts(lines: Iterable[str], exit_code: int | None) -> MissionFacts:
    """The goal driver's run: SUCCESS when every goal succeeded; the last goal's Nav2 error code."""
    last, end = None, None
    for line in lines:
        line = line.strip()
        last = GOAL_RESULT.search(line) or last
        end = GOALS_END.search(line) or end
    if end is None:
        word = "TIMEOUT" if exit_code in (None, 130) else "STACK"
        return MissionFacts(word, f"the goal list did not end; exit code {exit_code}",
                            result_code=int(last["code"]) if last else None)
    reached = end["reached"] == end["total"]
    detail = f"{end['total']} goals reached" if reached else (last.string if last else end.string)
    code = int(last["code"]) if last else None
    return MissionFacts("SUCCESS" if reached else "ABORT", detail, result_code=code, sim_time=float(end["s"]))


def tree_facts(lines: Iterable[str], exit_code: int | None) -> MissionFacts:
    """A nav-autonomy run: SUCCESS when its last cycle's root succeeded; the tag is that root status."""
    last = None
    for line in lines:
        if (cycle := BT_CYCLE.search(line)) is not None:
            last = cycle
    if last is None:
        word = "TIMEOUT" if exit_code in (None, 130) else "STACK"
        return MissionFacts(word, f"no cycle ended; exit code {exit_code}")
    leaf = f" at {last['leaf']!r}" if last["leaf"] else ""
    word = "SUCCESS" if last["status"] == "SUCCESS" else "ABORT"
    return MissionFacts(word, f"cycle {last['n']}: root {last['status']}{leaf}", tag=last["status"],
                        result_code=0 if word == "SUCCESS" else None)
