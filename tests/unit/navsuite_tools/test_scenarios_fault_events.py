"""The fault events of issue 45 in the scenario file: kill/freeze of each process, topic loss, clock
pause, obstacle on the path, odometry slip, the scenario's seed. Parsing and validation, what the worker
hands the injector, and the injector's pure parts (where an obstacle lands on the path, which process
a pid names, the freeze book). No ROS."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from navsuite_tools.scenarios import commands
from navsuite_tools.scenarios.injector import KINDS
from navsuite_tools.scenarios.process_faults import FreezeBook, role_pid, send, simulator_pid, target_of
from navsuite_tools.scenarios.schema import ScenarioError, parse_scenarios
from navsuite_tools.scenarios.schema_fields import INJECTED_EVENTS, LOSABLE_TOPICS
from navsuite_tools.scenarios.sim_events import point_along
from navsuite_tools.scenarios.worker import injector_spec
from ros_tools.runtime.requests import poll

REPO = Path(__file__).resolve().parents[3]


def _scenario(events: list[dict[str, Any]], **fields: Any) -> Any:
    document = {"scenarios": [{"name": "s1", "mission": {"goals": [[0, 0]]}, "events": events, **fields}]}
    return parse_scenarios(document, "file.yaml", REPO / "config", REPO)[0]


def _error(events: list[dict[str, Any]], **fields: Any) -> str:
    with pytest.raises(ScenarioError) as info:
        _scenario(events, **fields)
    return str(info.value)


def test_every_fault_event_loads_with_its_value() -> None:
    events = [{"at": 1, "kill_localization": None}, {"at": 2, "freeze_navigation": 3},
              {"at": 3, "freeze_simulator": 0.5}, {"at": 4, "topic_loss": {"topic": "scan", "duration": 2}},
              {"at": 5, "clock_pause": 2}, {"at": 6, "obstacle_on_path": {"ahead": 1, "radius": 0.2}},
              {"at": 7, "odom_slip": {"scale": 1.5, "duration": 4}}, {"at": 8, "kill_simulator": None}]
    scenario = _scenario(events)
    assert [(e.at, e.kind, e.value) for e in scenario.events] == [
        (1.0, "kill_localization", None), (2.0, "freeze_navigation", 3.0), (3.0, "freeze_simulator", 0.5),
        (4.0, "topic_loss", {"topic": "scan", "duration": 2.0}), (5.0, "clock_pause", 2.0),
        (6.0, "obstacle_on_path", {"ahead": 1.0, "radius": 0.2}),
        (7.0, "odom_slip", {"scale": 1.5, "duration": 4.0}), (8.0, "kill_simulator", None)]
    assert scenario.isolated                      # a localization event runs the isolated layout


@pytest.mark.parametrize(("event", "field", "value"), [
    ({"freeze_navigation": 0}, "freeze_navigation", "0"),
    ({"freeze_localization": None}, "freeze_localization", "None"),
    ({"clock_pause": -1}, "clock_pause", "-1"),
    ({"kill_simulator": 3}, "kill_simulator", "3"),
    ({"topic_loss": {"topic": "clock", "duration": 1}}, "topic_loss.topic", "'clock'"),
    ({"topic_loss": {"topic": "scan"}}, "topic_loss", "{'topic': 'scan'}"),
    ({"topic_loss": {"topic": "scan", "duration": 0}}, "topic_loss.duration", "0"),
    ({"odom_slip": {"scale": -0.5, "duration": 1}}, "odom_slip.scale", "-0.5"),
    ({"odom_slip": [1.2, 3]}, "odom_slip", "[1.2, 3]"),
    ({"obstacle_on_path": {"ahead": 1, "radius": 0.2, "x": 1}}, "obstacle_on_path",
     "{'ahead': 1, 'radius': 0.2, 'x': 1}"),
    ({"obstacle_on_path": {"ahead": "far", "radius": 0.2}}, "obstacle_on_path.ahead", "'far'"),
    ({"freeze_planner": 2}, "freeze_planner", "'freeze_planner'"),
])
def test_a_bad_fault_event_names_its_field_and_value(event: dict[str, Any], field: str, value: str) -> None:
    message = _error([{"at": 5, **event}])
    assert message.startswith(f"file.yaml: scenario 's1': events[0].{field}: "), message
    assert f"(got {value})" in message, message


def test_the_seed_is_checked_and_reaches_sim2d(tmp_path: Path) -> None:
    assert "seed" in _error([], seed=-1) and "(got -1)" in _error([], seed=-1)
    scenario = _scenario([], seed=4)
    assert scenario.seed == 4 and not scenario.isolated
    plan = commands.plan(scenario, tmp_path, REPO)
    overlay = next(text for path, text in plan.files.items() if path.name == "sim2d_overlay.yaml")
    assert "seed: 4" in overlay


def test_the_injector_gets_every_fault_event_and_knows_each_kind() -> None:
    events = [{"at": 2, "topic_loss": {"topic": "odom", "duration": 1}}, {"at": 3, "freeze_localization": 2}]
    spec = injector_spec(_scenario(events))
    assert spec is not None
    assert json.loads(spec.cmd[-1]) == [{"at": 2.0, "topic_loss": {"topic": "odom", "duration": 1.0}},
                                        {"at": 3.0, "freeze_localization": 2.0}]
    assert set(KINDS) == set(INJECTED_EVENTS)


def test_the_losable_topics_are_sim2ds() -> None:
    from sim2d.core.disturbances import LOSABLE_TOPICS as SIM2D_TOPICS

    assert LOSABLE_TOPICS == SIM2D_TOPICS


def test_an_obstacle_on_the_path_lands_ahead_of_the_robot_and_clear_of_the_goal() -> None:
    path = [(float(x), 0.0) for x in range(6)]                 # 5 m along +x
    assert point_along(path, (1.1, 0.2), 1.5, 0.7) == pytest.approx((2.5, 0.0))
    assert point_along(path, (3.0, 0.0), 1.5, 0.7) == pytest.approx((4.3, 0.0))   # pulled back from the end
    assert point_along(path, (4.6, 0.0), 1.0, 0.7) is None                        # too little path left
    assert point_along([(0.0, 0.0)], (0.0, 0.0), 1.0, 0.1) is None


def test_a_process_target_is_read_from_its_lockstep_name() -> None:
    assert target_of("freeze_localization") == "localization"
    assert role_pid("navigation", "nav2:42") == 42 and role_pid("navigation", "navigation:7") == 7
    assert role_pid("localization", "localization:9") == 9
    assert role_pid("localization", "nav2:9") is None and role_pid("navigation", "SmNav2Test1:3") is None


def test_the_simulator_is_found_among_the_scenarios_processes_only(tmp_path: Path) -> None:
    fake = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)", "-m", "sim2d.ros.cli"])
    try:
        # Until the child has exec'd, its /proc cmdline is still this process's: wait for the exec.
        assert poll(lambda: b"sim2d.ros.cli" in Path(f"/proc/{fake.pid}/cmdline").read_bytes(), 5.0, 0.01)
        assert simulator_pid(os.getpid()) == fake.pid
        assert simulator_pid(fake.pid) is None                # not under that ancestor
    finally:
        fake.kill()
        fake.wait()


def test_a_freeze_stops_the_process_and_the_book_continues_it() -> None:
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        book = FreezeBook()
        book.freeze(child.pid, os.getpid())
        assert _becomes(child.pid, lambda state: state == "T")
        book.thaw_all()
        assert _becomes(child.pid, lambda state: state != "T") and not book.frozen
        assert not book.thaw(child.pid)                      # only what it froze, once
        with pytest.raises(PermissionError):
            send(os.getppid(), signal.SIGSTOP, os.getpid())  # not a process of this run: nothing sent
    finally:
        child.kill()
        child.wait()


def _becomes(pid: int, wanted: Callable[[str], bool], timeout: float = 5.0) -> bool:
    """Whether the process's state letter (/proc/<pid>/stat) satisfies ``wanted`` within ``timeout`` s:
    a signal is delivered asynchronously."""
    def state() -> str:
        text = Path(f"/proc/{pid}/stat").read_text()
        return text[text.rindex(")") + 2]

    return poll(lambda: wanted(state()), timeout, 0.01)
