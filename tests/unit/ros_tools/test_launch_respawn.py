"""Respawn in the launcher (launch's ``respawn``/``respawn_delay``): the policy, then fake processes."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from ros_tools.launch import Launcher, LaunchError, ProcessSpec
from ros_tools.launch_respawn import Respawn, RespawnTracker
from tests.helpers.fake_processes import dying, lives


# ------------------------------------------------------------------------------------------ policy
def test_a_respawning_process_restarts_after_its_delay_until_it_dies_too_often() -> None:
    tracker = RespawnTracker(Respawn(enabled=True, delay=2.0, max_deaths=2, window=60.0))
    assert tracker.died(10.0) == 12.0
    assert tracker.died(20.0) == 22.0
    assert tracker.died(30.0) is None  # the third death within 60 s: given up
    assert "died 3 times within 60 s (last exit code -9)" in tracker.given_up_message("nav2", -9)


def test_deaths_older_than_the_window_are_forgotten() -> None:
    tracker = RespawnTracker(Respawn(enabled=True, max_deaths=1, window=10.0))
    assert tracker.died(0.0) == 0.0
    assert tracker.died(10.5) == 10.5  # the first death left the window
    assert tracker.died(11.0) is None


def test_without_respawn_every_death_is_final() -> None:
    assert RespawnTracker(Respawn()).died(0.0) is None


@pytest.mark.parametrize("bad", [{"delay": -1.0}, {"max_deaths": 0}, {"window": 0.0}])
def test_bad_respawn_settings_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError, match="respawn"):
        Respawn(enabled=True, **bad)  # type: ignore[arg-type]


def test_a_bad_respawn_setting_is_a_launch_error_naming_the_process(tmp_path: Path) -> None:
    launcher = Launcher(output=lambda _line: None, color=False)
    spec = ProcessSpec("nav2", dying(tmp_path / "n", []), respawn=True, respawn_delay=-1.0)
    with pytest.raises(LaunchError, match="nav2: respawn delay"):
        launcher.start([spec])


# --------------------------------------------------------------------------------- fake processes
def _wait_for(condition: Callable[[], bool], deadline_s: float = 30.0) -> bool:
    deadline = time.monotonic() + deadline_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return False


def test_a_killed_process_is_started_again_with_the_same_command_and_environment(tmp_path: Path) -> None:
    counter, lines = tmp_path / "lives", list[str]()
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0, log_dir=tmp_path / "logs")
    spec = ProcessSpec("nav2", dying(counter, [247]), ready="ready", env={"FAKE_TAG": "same"},
                       respawn=True)
    code = launcher.run([spec], until=lambda: "[launch] nav2 is ready again after its respawn" in lines)
    assert code == 0, lines
    assert lives(counter) == 2
    assert "[nav2] life 2 ready env=same" in lines
    assert any(line.startswith("[launch] WARN: nav2 died with exit code 247; respawning it (restart 1 of")
               for line in lines), lines
    log = (tmp_path / "logs" / "nav2.log").read_text()
    assert "life 1 ready" in log and "life 2 ready" in log  # the log goes on across the respawn


def test_a_process_that_keeps_dying_is_given_up_with_one_message_and_the_launch_ends(tmp_path: Path) -> None:
    counter, lines = tmp_path / "lives", list[str]()
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    specs = [ProcessSpec("sim", dying(tmp_path / "sim", []), ready="ready"),
             ProcessSpec("nav2", dying(counter, [3, 3, 3, 3]), ready="ready", respawn=True,
                         respawn_max_deaths=2)]
    assert launcher.run(specs) == 3
    assert lives(counter) == 3  # the first life and two restarts
    given_up = [line for line in lines if "not respawning it again" in line]
    assert given_up == ["[launch] ERROR: nav2 died 3 times within 120 s (last exit code 3); not respawning "
                        "it again (the limit is 2 restarts); stopping the launch"]
    assert not any("ERROR: nav2 died with exit code" in line for line in lines)
    assert all(r.proc.poll() is not None for r in launcher.running), "a process was left running"


def test_a_process_without_respawn_still_ends_the_launch(tmp_path: Path) -> None:
    counter, lines = tmp_path / "lives", list[str]()
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    assert launcher.run([ProcessSpec("sim", dying(counter, [5]), ready="ready")]) == 5
    assert lives(counter) == 1
    assert "[launch] ERROR: sim died with exit code 5; stopping the launch" in lines


def test_the_respawn_waits_for_its_delay_and_shutdown_stops_the_new_life(tmp_path: Path) -> None:
    counter, lines = tmp_path / "lives", list[str]()
    launcher = Launcher(output=lines.append, color=False, shutdown_grace=2.0)
    spec = ProcessSpec("nav2", dying(counter, [1]), ready="ready", respawn=True, respawn_delay=3.0)
    launcher.start([spec])
    waiter = threading.Thread(target=launcher.wait, daemon=True)
    waiter.start()
    try:
        assert _wait_for(lambda: any("respawning it" in line for line in lines))
        assert lives(counter) == 1  # the death is seen; the restart waits for its delay
        assert _wait_for(lambda: lives(counter) == 2)
    finally:
        launcher.stop()
        waiter.join(5.0)
        launcher.shutdown()
    assert all(r.proc.poll() is not None for r in launcher.running)
