"""nav-bringup: its command line, the processes it starts (in order, with use_sim_time and the
readiness lines the launcher waits for), and that it exits non-zero when the simulator dies."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from nav_stack.ros.bringup import nav_bringup as bringup
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait
from tests.helpers.process_tree import child_pids, cmdline


def _specs(*argv: str) -> list:
    return bringup.process_specs(bringup.parse_args(argv))


@pytest.fixture(autouse=True)
def _default_layout(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """The command-line tests check the default layout, so a suite run with NAVSUITE_LAYOUT=isolated
    (issue 17: every system test in both layouts) must not change it under them; the tests that
    start real processes keep the variable and run in the layout it names."""
    if request.node.get_closest_marker("ros") is None:
        monkeypatch.delenv(bringup.LAYOUT_ENV, raising=False)


def test_default_launch_is_one_nav2_process_in_lockstep_with_the_sim():
    specs = _specs("--rtf", "2")
    assert [s.name for s in specs] == ["sim2d", "initial_pose", "nav2"]
    sim = specs[0].cmd
    assert sim[sim.index("--rtf") + 1] == "2" and sim[sim.index("--x") + 1] == "-2.0"
    assert sim[sim.index("--lockstep-participants") + 1] == "nav2"
    assert specs[2].ready == "bringup: component all is active"
    assert specs[1].required is False and "use_sim_time:=true" in specs[1].cmd


def test_isolated_launch_starts_sim_localization_initial_pose_then_navigation():
    specs = _specs("--isolated", "--executor", "single")
    assert [s.name for s in specs] == ["sim2d", "localization", "initial_pose", "navigation"]
    sim = specs[0].cmd
    assert sim[sim.index("--lockstep-participants") + 1] == "localization,navigation"
    assert specs[1].ready == "bringup: component localization is active"
    assert specs[2].required is False and "AMCL confirmed" in specs[2].ready
    assert all(spec.env["NAVSUITE_EXECUTOR"] == "single" for spec in specs)
    assert "--lockstep-participants" not in _specs("--no-lockstep")[0].cmd


def test_the_layout_variable_makes_isolated_the_default(monkeypatch: pytest.MonkeyPatch) -> None:
    """NAVSUITE_LAYOUT=isolated runs every nav-bringup (the demos', the system tests') in two node
    processes; --slam keeps its own layout; an unknown value is refused naming the variable."""
    monkeypatch.setenv(bringup.LAYOUT_ENV, "isolated")
    assert [s.name for s in _specs()] == ["sim2d", "localization", "initial_pose", "navigation"]
    assert [s.name for s in _specs("--slam")][:2] == ["sim2d", "slam"]
    monkeypatch.setenv(bringup.LAYOUT_ENV, "one-process")
    assert [s.name for s in _specs()] == ["sim2d", "initial_pose", "nav2"]
    monkeypatch.setenv(bringup.LAYOUT_ENV, "split")
    with pytest.raises(SystemExit):
        _specs()


def test_slam_mode_runs_slam_and_map_saver_instead_of_map_server_and_amcl():
    specs = _specs("--slam", "--x", "-2.0", "--y", "-0.5")
    assert [s.name for s in specs] == ["sim2d", "slam", "map_saver", "lifecycle_manager_slam", "navigation"]
    assert "map_start_pose:=[-2.0, -0.5, 0.0]" in specs[1].cmd


def test_a_world_brings_its_map_and_spawn_unless_given():
    house = _specs("--world", "turtlebot3_house")
    sim, nav2, initial_pose = house[0].cmd, house[2].cmd, house[1].cmd
    assert sim[sim.index("--x") + 1 :][:5:2] == ["-2.0", "1.0", "0.0"]
    assert nav2[nav2.index("--map") + 1].endswith("maps/turtlebot3_house.yaml")
    assert "x:=-2.0" in initial_pose and "y:=1.0" in initial_pose
    given = _specs("--world", "turtlebot3_house", "--x", "-3.0", "--map", "maps/turtlebot3_world.yaml")
    assert given[0].cmd[given[0].cmd.index("--x") + 1] == "-3.0"
    assert given[2].cmd[given[2].cmd.index("--map") + 1].endswith("maps/turtlebot3_world.yaml")
    # no --world and the shipped parameters: the default world's map, by absolute path (the file's
    # relative yaml_filename would load only from the repository); own --params keep their own map
    default = _specs()[2].cmd
    assert Path(default[default.index("--map") + 1]).is_absolute()
    assert default[default.index("--map") + 1].endswith("maps/turtlebot3_world.yaml")
    assert "--map" not in _specs("--params", "config/nav2_params.yaml")[2].cmd
    # Nav2's own file leaves yaml_filename empty (its launch file's `map` argument fills it): the world's
    jazzy = _specs("--params", "config/jazzy/nav2_params.yaml")[2].cmd
    assert jazzy[jazzy.index("--map") + 1].endswith("maps/turtlebot3_world.yaml")


def test_tb4_brings_its_parameter_file_and_the_simulator_its_model():
    sim, _, nav2 = (spec.cmd for spec in _specs("--robot", "tb4", "--world", "depot_large"))
    assert sim[sim.index("--robot") + 1] == "tb4"
    assert nav2[nav2.index("--params") + 1].endswith("config/nav2_params_tb4.yaml")
    assert nav2[nav2.index("--map") + 1].endswith("maps/depot_large.yaml")
    waffle = _specs()[2].cmd
    assert waffle[waffle.index("--params") + 1].endswith("config/nav2_params.yaml")
    chosen = _specs("--robot", "tb4", "--params", str(bringup.REPO / "config" / "nav2_params.yaml"))[2].cmd
    assert chosen[chosen.index("--params") + 1].endswith("config/nav2_params.yaml")  # --params wins


def test_no_sim_variants():
    assert [s.name for s in _specs("--no-sim", "--no-initial-pose")] == ["nav2"]
    isolated = _specs("--no-sim", "--no-initial-pose", "--isolated")
    assert [s.name for s in isolated] == ["localization", "navigation"]


@pytest.mark.parametrize(("argv", "message"), [
    (["--slam", "--map", "maps/turtlebot3_world.yaml"], "--slam builds its own map"),
    (["--slam", "--isolated"], "--slam always runs its nodes as separate processes"),
    (["--params", "/nonexistent.yaml"], "--params: no such file"),
    (["--rtf", "fast"], "--rtf must be a positive number"),
])
def test_bad_options_exit_2_with_a_clear_message(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_info:
        bringup.main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


def test_a_file_the_stack_cannot_run_is_refused_before_any_process_starts(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 41: an unknown plugin ends bringup at once, every problem in one message naming the
    file, section, key, value and the supported values; nothing is launched."""
    bad = tmp_path / "bad_params.yaml"
    bad.write_text(
        "controller_server:\n  ros__parameters:\n    controller_plugins: [FollowPath]\n"
        "    FollowPath: {plugin: 'my_controllers::Teleporter'}\n"
        "behavior_server:\n  ros__parameters:\n    behavior_plugins: [spin, dance]\n"
        "    dance: {plugin: 'my_behaviors::Dance'}\n")
    monkeypatch.setattr(bringup, "launch", lambda args: pytest.fail("the launch must not start"))
    assert bringup.main(["--params", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}: controller_server: FollowPath.plugin: 'my_controllers::Teleporter' is not a plugin " \
           "this stack has (supported: DWBLocalPlanner" in err, err
    assert f"{bad}: behavior_server: dance.plugin: 'my_behaviors::Dance'" in err, err
    assert "2 setting(s) this stack cannot run" in err


@pytest.mark.ros
@pytest.mark.slow
def test_bringup_exits_non_zero_when_the_simulator_is_killed():
    stack = Bringup()
    try:
        stack.wait_for_line(READY, timeout=240.0)
        sims = [pid for pid in child_pids(stack.proc.pid) if "sim2d.ros.cli" in cmdline(pid)]
        assert len(sims) == 1, [cmdline(pid) for pid in child_pids(stack.proc.pid)]
        children = child_pids(stack.proc.pid)
        os.kill(sims[0], signal.SIGKILL)
        wait(lambda: stack.proc.poll() is not None, 60.0, "nav-bringup to exit")
        assert stack.proc.returncode != 0
        wait(lambda: any("sim2d died" in line for line in stack.lines), 10.0, "the launcher's error line")
        assert not [pid for pid in children if os.path.exists(f"/proc/{pid}")], "orphaned child processes"
    finally:
        stack.stop()


@pytest.mark.ros
@pytest.mark.slow
def test_a_broken_map_ends_the_launch_with_the_cause_and_the_log_file(tmp_path: Path) -> None:
    """map_server cannot configure: the manager aborts the bringup, and instead of waiting out the
    readiness timeout the launch ends at once, showing map_server's error and where the full log is."""
    broken = tmp_path / "broken.yaml"
    broken.write_text("image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
                      "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    command = [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup", "--rtf", "max",
               "--map", str(broken), "--log-dir", str(tmp_path / "logs")]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120.0)
    assert done.returncode == 1, done.stdout + done.stderr
    assert f"map image {tmp_path / 'nowhere.pgm'} does not exist" in done.stdout, done.stdout
    assert "lifecycle_manager_localization aborted the bringup" in done.stdout, done.stdout
    # the process holding map_server: nav2 in one process, localization in the isolated layout
    holder = next(spec.name for spec in _specs("--map", str(broken)) if str(broken) in spec.cmd)
    log = tmp_path / "logs" / f"{holder}.log"
    # how many lines the process printed before it ended varies; at most 15 are shown
    shown = rf"last \d+ lines of {holder} \(all of them in {re.escape(str(log))}\)"
    assert re.search(shown, done.stdout), done.stdout
    assert "Configuring" in log.read_text()
