"""The injected events' pure parts: which process kill_navigation may kill, and what the worker hands
the injector (every event applied during the run, none of those set before the start)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from navsuite_tools.scenarios.navigation_kill import descends_from, kill_navigation, navigation_pid, parent_of
from navsuite_tools.scenarios.schema import parse_scenarios
from navsuite_tools.scenarios.worker import injector_spec


@pytest.mark.parametrize(("participant", "pid"), [
    ("nav2:4242", 4242), ("navigation:17", 17), ("localization:17", None), ("scenario_goals:5", None),
    ("nav2", None), ("nav2:x", None),
])
def test_only_the_process_running_bt_navigator_and_the_controller_is_a_target(participant: str,
                                                                              pid: int | None) -> None:
    assert navigation_pid(participant) == pid


def test_descent_walks_the_parents_up_to_init() -> None:
    parents = {30: 20, 20: 10, 10: 1, 40: 1}
    assert descends_from(30, 10, parents.get)
    assert not descends_from(40, 10, parents.get)
    assert not descends_from(10, 10, parents.get)       # a process is not its own descendant
    assert not descends_from(99, 10, parents.get)       # gone: nothing to kill


def test_the_kill_refuses_a_process_outside_the_scenario_and_kills_a_child() -> None:
    assert parent_of(os.getpid()) == os.getppid()
    with pytest.raises(PermissionError, match="not a process of this scenario"):
        kill_navigation(os.getppid(), os.getpid())
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        assert kill_navigation(child.pid, os.getpid()) == f"pid {child.pid}"
        assert child.wait(timeout=10) == -9
    finally:
        child.kill()


def test_the_injector_gets_the_run_time_events_and_not_the_initial_battery() -> None:
    document = {"scenarios": [{"name": "s", "mission": {"goals": [[0, 0]]}, "events": [
        {"at": 0, "battery": 0.5}, {"at": 1, "kidnap": [1, 2]}, {"at": 2, "lidar_dropout": 3},
        {"at": 3, "obstacle": [1, 1, 0.2]}, {"at": 4, "kill_navigation": None}]}]}
    spec = injector_spec(parse_scenarios(document, "f.yaml")[0])
    assert spec is not None
    assert json.loads(spec.cmd[-1]) == [
        {"at": 1.0, "kidnap": [1.0, 2.0, 0.0]}, {"at": 2.0, "lidar_dropout": 3.0},
        {"at": 3.0, "obstacle": [1.0, 1.0, 0.2]}, {"at": 4.0, "kill_navigation": None}]
    assert injector_spec(parse_scenarios({"scenarios": [{**document["scenarios"][0], "events": [
        {"at": 0, "battery": 0.5}]}]}, "f.yaml")[0]) is None
