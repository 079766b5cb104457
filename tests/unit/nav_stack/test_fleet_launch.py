"""nav-bringup --robots N / --fleet FILE (issue 48): the processes a fleet launch starts (one simulator with
every robot, one namespaced stack and initial pose per robot, lockstep waiting for every stack), the
parameter files each robot gets, the options a fleet refuses, and nav-goal's --namespace."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from nav_stack.ros.bringup import nav_bringup as bringup
from nav_stack.ros.bringup.bringup_components import component_role
from nav_stack.ros.tools.goal_cli import _parser as goal_parser

REPO = Path(__file__).resolve().parents[3]


@pytest.fixture(autouse=True)
def _default_layout(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(bringup.LAYOUT_ENV, raising=False)


def _specs(*argv: str) -> list:
    return bringup.process_specs(bringup.parse_args(argv))


def _after(cmd: list[str], flag: str) -> str:
    return cmd[cmd.index(flag) + 1]


def test_robots_n_starts_one_simulator_and_one_namespaced_stack_per_robot() -> None:
    specs = _specs("--robots", "2", "--rtf", "max")
    assert [s.name for s in specs] == ["sim2d", "robot1/initial_pose", "robot2/initial_pose", "robot1/nav2",
                                       "robot2/nav2"]
    sim = specs[0].cmd
    assert _after(sim, "--lockstep-participants") == "robot1/nav2,robot2/nav2"
    fleet = yaml.safe_load(_after(sim, "-p").removeprefix("fleet:="))
    assert fleet == ["robot1:waffle:-2.0,-0.5,0.0", "robot2:waffle:-0.55,-0.55,0.7854"]  # the world's spawns
    assert "lockstep.startup_timeout:=120.0" in sim and "--stamped" in sim
    for robot, spec in (("robot1", specs[3]), ("robot2", specs[4])):
        assert _after(spec.cmd, "--namespace") == robot and "--stamped-cmd-vel" in spec.cmd
        assert spec.ready == "bringup: component all is active" and not spec.ready_before_next
        assert [Path(p).name for p in spec.cmd if p.endswith(".yaml")] == [
            "nav2_params.yaml", "robot_namespace_overlay.yaml", "turtlebot3_world.yaml"]
    initial = specs[2].cmd
    assert "__ns:=/robot2" in initial and "/tf:=/robot2/tf" in initial
    assert "x:=-0.55" in initial and "yaw:=0.7854" in initial
    assert not specs[2].required and not specs[2].ready_before_next


def test_a_fleet_file_mixes_models_each_with_its_own_parameter_file(tmp_path: Path) -> None:
    path = tmp_path / "fleet.yaml"
    path.write_text("- {name: alpha, model: tb4, x: -14.2, y: 0.051}\n"
                    "- {name: beta, x: -11.7, y: 0.051, yaw: 3.14}\n")
    specs = _specs("--fleet", str(path), "--world", "depot_large", "--isolated")
    assert [s.name for s in specs] == ["sim2d", "alpha/localization", "beta/localization",
                                       "alpha/initial_pose", "beta/initial_pose", "alpha/navigation",
                                       "beta/navigation"]
    sim = specs[0].cmd
    assert _after(sim, "--robot") == "tb4" and _after(sim, "--x") == "-14.2"
    assert _after(sim, "--lockstep-participants") == ("alpha/localization,alpha/navigation,"
                                                      "beta/localization,beta/navigation")
    assert yaml.safe_load(_after(sim, "-p").removeprefix("fleet:=")) == [
        "alpha:tb4:-14.2,0.051,0.0", "beta:waffle:-11.7,0.051,3.14"]
    assert _after(specs[1].cmd, "--params").endswith("nav2_params_tb4.yaml")
    assert _after(specs[2].cmd, "--params").endswith("config/nav2_params.yaml")
    assert specs[3].ready == "AMCL confirmed the initial pose"


def test_given_parameter_files_serve_every_robot_as_nav2s_cloned_launch() -> None:
    multirobot = str(REPO / "config" / "fleet" / "nav2_multirobot_params_all.yaml")
    specs = _specs("--robots", "3", "--world", "depot_large", "--params", multirobot)
    stacks = [s for s in specs if s.name.endswith("/nav2")]
    assert [s.name for s in stacks] == ["robot1/nav2", "robot2/nav2", "robot3/nav2"]
    for spec in stacks:
        assert [p for p in spec.cmd if p.endswith("params_all.yaml")] == [multirobot]
        assert _after(spec.cmd, "--map").endswith("maps/depot_large.yaml")  # Nav2's file names no map


def test_the_fleets_files_are_checked_and_warned_about_before_anything_starts(
        capsys: pytest.CaptureFixture[str]) -> None:
    multirobot = "config/fleet/nav2_multirobot_params_all.yaml"
    assert bringup.check_params(bringup.parse_args(["--robots", "2", "--params", multirobot])) is None
    err = capsys.readouterr().err
    assert "warning: bt_navigator: odom_topic: /odom is outside the robot's namespace" in err
    assert bringup.check_params(bringup.parse_args(["--robots", "2"])) is None
    assert capsys.readouterr().err == ""   # the robot files with the overlay


@pytest.mark.parametrize(("argv", "message"), [
    (["--robots", "2", "--slam"], "--slam maps with one robot"),
    (["--robots", "2", "--x", "1.0"], "--x/--y/--yaw place one robot"),
    (["--robots", "2", "--fleet", "f.yaml"], "not allowed with argument"),
    (["--robots", "0"], "--robots: a fleet needs at least one robot, got 0"),
    (["--robots", "40"], "--robots: only"),
    (["--fleet", "/nonexistent/fleet.yaml"], "--fleet: no such file"),
])
def test_bad_fleet_options_exit_2_with_a_message(argv: list[str], message: str,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        bringup.parse_args(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


def test_one_robot_launches_stay_as_they_were() -> None:
    args = bringup.parse_args(["--rtf", "2"])
    assert args.members == ()
    assert [s.name for s in bringup.process_specs(args)] == ["sim2d", "initial_pose", "nav2"]
    assert component_role("all") == "nav2" and component_role("all", "/robot1/") == "robot1/nav2"


def test_nav_goal_namespace_is_checked_and_made_absolute() -> None:
    assert goal_parser().parse_args(["--namespace", "robot2", "goto", "1", "2"]).namespace == "/robot2"
    nested = goal_parser().parse_args(["--namespace", "/fleet/robot2/", "goto", "1", "2"])
    assert nested.namespace == "/fleet/robot2"
    assert goal_parser().parse_args(["goto", "1", "2"]).namespace == ""
    with pytest.raises(SystemExit):
        goal_parser().parse_args(["--namespace", "2robot", "goto", "1", "2"])


def test_the_fleet_options_are_documented_in_the_help() -> None:
    text = bringup._parser().format_help()
    assert "--robots N" in text and "--fleet FILE" in text
