"""sim2d command line: flags and parameter files validated before ROS starts (exit 2, one line)."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim2d.ros.cli import main, parse
from sim2d.ros.config import build_config


def test_flags_override_the_parameter_file(tmp_path: Path) -> None:
    params = tmp_path / "p.yaml"
    params.write_text("sim2d:\n  ros__parameters:\n    robot: burger\n    lidar: {rate: 10}\n"
                      "/**:\n  ros__parameters:\n    use_sim_time: false\n    other_node_knob: 3\n")
    values, ros_args = parse(["--params-file", str(params), "--rtf", "max", "--x", "0.5", "--yaw", "1",
                              "--ros-args", "-r", "scan:=base_scan"])
    config = build_config(values)
    assert config.node.robot == "burger" and config.lidar.rate == 10.0
    assert config.node.real_time_factor == 0.0
    pose = config.sim.initial_pose
    assert (pose.x, pose.y, pose.yaw) == (0.5, -0.5, 1.0)
    assert ros_args == ["--ros-args", "-r", "scan:=base_scan"]


def test_a_world_flag_alone_spawns_at_the_worlds_first_spawn() -> None:
    from sim2d.core.world import load_world

    def spawn(argv: list[str]) -> tuple[float, float, float]:
        pose = build_config(parse(argv)[0]).sim.initial_pose
        return pose.x, pose.y, pose.yaw

    assert spawn(["--world", "office_small"]) == load_world("office_small").spawns[0] != spawn([])
    assert spawn(["--world", "office_small", "--x", "1.5"])[:2] == (1.5, -0.5)  # flags: the file's pose
    assert spawn(["--world", "office_small", "--ros-args", "-p", "initial_pose.x:=2.0"])[0] == 2.0


def test_shipped_config_matches_the_defaults() -> None:
    values, _ = parse([])
    assert build_config(values) == build_config({})


@pytest.mark.parametrize(("argv", "message"), [
    (["--rtf", "fast"], "argument --rtf"),
    (["--robot", "kobuki"], "argument --robot"),
    (["--world", "atlantis"], "world 'atlantis' not found"),
    (["--params-file", "{bad}"], "bad.yaml: sim2d.ros__parameters: lidar.beams: expected int"),
    (["--params-file", "{unknown}"], "unknown.yaml: sim2d.ros__parameters: lidar.colour: unknown parameter"),
    (["--world", "{world}"], "world.yaml: obstacles[0].radius: must be > 0"),
])
def test_bad_input_is_one_line_naming_file_and_field(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                     argv: list[str], message: str) -> None:
    (tmp_path / "bad.yaml").write_text("sim2d:\n  ros__parameters:\n    lidar: {beams: many}\n")
    (tmp_path / "unknown.yaml").write_text("sim2d:\n  ros__parameters:\n    lidar: {colour: red}\n")
    (tmp_path / "world.yaml").write_text("obstacles: [{type: circle, center: [0, 0], radius: 0}]\n")
    files = {name: tmp_path / f"{name}.yaml" for name in ("bad", "unknown", "world")}
    argv = [a.format(**files) for a in argv]
    with pytest.raises(SystemExit) as exit_info:
        raise SystemExit(main(argv))
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("sim2d: error: ") and message in err


def test_ros_args_parameters_override_the_config_file_and_flags_override_both():
    from sim2d.ros.cli import parse

    values, ros_args = parse(["--rtf", "2", "--ros-args", "-p", "odometry.ideal:=true",
                              "-p", "real_time_factor:=7.0", "-p", "use_sim_time:=false"])
    assert values["odometry.ideal"] is True  # was silently ignored before: the file's value won
    assert values["real_time_factor"] == 2.0  # the explicit flag wins
    assert "use_sim_time" not in values and "use_sim_time:=false" in ros_args  # left to rclpy


def test_lockstep_flags_set_the_lockstep_parameters() -> None:
    from sim2d.ros.cli import parse_command_line

    assert build_config(parse([])[0]).lockstep.enabled is False
    assert build_config(parse(["--lockstep"])[0]).lockstep.enabled is True
    command = parse_command_line(["--lockstep-participants", "nav2, localization", "--executor", "single"])
    lockstep = build_config(command.values).lockstep
    assert lockstep.enabled is True and lockstep.participants == ("nav2", "localization")
    assert command.executor == "single"
    values, _ = parse(["--ros-args", "-p", "lockstep.participants:=[nav2]", "-p", "lockstep.max_lead:=0.1"])
    assert build_config(values).lockstep.participants == ("nav2",)


@pytest.mark.parametrize(("argv", "message"), [
    (["--lockstep-participants", ","], "argument --lockstep-participants"),
    (["--executor", "multi"], "argument --executor"),
    (["--ros-args", "-p", "lockstep.max_lead:=0.001"], "lockstep.max_lead: must be at least physics_step"),
    (["--ros-args", "-p", "lockstep.timeout:=0"], "lockstep.timeout: must be > 0"),
    (["--ros-args", "-p", "lockstep.participants:=nav2"], "lockstep.participants: expected list of str"),
])
def test_bad_lockstep_input_is_one_line(capsys: pytest.CaptureFixture[str], argv: list[str],
                                        message: str) -> None:
    with pytest.raises(SystemExit) as exit_info:
        raise SystemExit(main(argv))
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("sim2d: error: ") and message in err
