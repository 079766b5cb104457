"""What the scenarios of config/scenarios/farm_selftest.yaml end with, by scenario: (result, result_code).

One table for both backends: tests/system/test_scenarios.py checks the local backend's run against
it, tests/system/test_scenarios_ray.py the Ray backend's, so the two are held to the same verdicts
without the Ray test paying for a second local run of the same scenarios (two whole stacks, about
30 s of wall time on two cores).
"""

from __future__ import annotations

from pathlib import Path

SELFTEST = Path(__file__).resolve().parents[2] / "config" / "scenarios" / "farm_selftest.yaml"
#: short_goal passes; unreachable_goal_aborts expects the planner's NO_VALID_PATH (208) and gets it;
#: built_to_fail gets the same ABORT but expects SUCCESS, so the farm fails it.
SELFTEST_VERDICTS = {"short_goal": ("SUCCESS", 0), "unreachable_goal_aborts": ("ABORT", 208),
                     "built_to_fail": ("ABORT", 208)}
