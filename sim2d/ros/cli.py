"""Command line: ``sim2d --world turtlebot3_world --robot waffle --rtf 5 --x -2.0 --y -0.5 --yaw 0``.

``--robot`` is one of sim2d.core.robot.ROBOTS: ``waffle``, ``burger`` (TurtleBot3, LDS-01 lidar) or
``tb4`` (TurtleBot4: round Create 3 base, RPLIDAR A1 in ``rplidar_link``).

``--lockstep`` makes the simulator wait for the stack (never more than ``lockstep.max_lead`` of sim
time ahead of the slowest participant); ``--lockstep-participants nav2,localization`` also holds
the first step until those roles have reported. ``--rtf`` still caps the speed on top of that.

Parameters come from config/sim2d.yaml (Nav2 layout ``sim2d: ros__parameters:``; ``--params-file``
picks another), then the flags override them; anything after ``--ros-args`` goes to rclpy (remaps,
``-p name:=value``). The whole configuration, including the world file, is validated before ROS
starts: a bad flag, parameter file or world, or a spawn pose inside (or within the robot's
circumradius of) an obstacle, gives one line ``sim2d: error: <file>: <field>: ...`` and exit code 2.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

import yaml

from navsuite_data import config_path, resolve, searched
from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument, executor_kind
from sim2d.core.robot import ROBOTS
from sim2d.ros.config import ParamValue, SimConfig, build_config, coerce, defaults, load_params_file

DEFAULT_PARAMS = config_path("sim2d.yaml")  # shipped data (navsuite_data)
EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_USAGE, f"sim2d: error: {message}\n")


def _rtf(text: str) -> float:
    if text.lower() in ("max", "inf"):
        return 0.0
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive number or 'max', got {text!r}") from None
    if value < 0.0:
        raise argparse.ArgumentTypeError(f"must be a positive number or 'max', got {text!r}")
    return value


def _roles(text: str) -> tuple[str, ...]:
    roles = tuple(role.strip() for role in text.split(",") if role.strip())
    if not roles:
        raise argparse.ArgumentTypeError(f"expected comma-separated roles (nav2,localization), got {text!r}")
    return roles


@dataclass(frozen=True)
class CommandLine:
    """A parsed command line: parameter values, rclpy's arguments and the executor kind (None: default)."""

    values: dict[str, ParamValue]
    ros_args: list[str]
    executor: str | None


def parse(argv: list[str]) -> tuple[dict[str, ParamValue], list[str]]:
    """Parameter values (file, then flags) and the rclpy arguments of a command line."""
    command = parse_command_line(argv)
    return command.values, command.ros_args


def parse_command_line(argv: list[str]) -> CommandLine:
    """Everything ``main`` needs from a command line; ValueError on a bad parameter file or value."""
    ros_args: list[str] = []
    if "--ros-args" in argv:
        split = argv.index("--ros-args")
        argv, ros_args = argv[:split], argv[split:]
    parser = _Parser(prog="sim2d", description="2D TurtleBot simulator on the ROS 2 graph.")
    parser.add_argument("--world", help="world name (sim2d/worlds/) or world/map_server YAML path")
    parser.add_argument("--robot", choices=sorted(ROBOTS))
    parser.add_argument("--rtf", type=_rtf, help="real-time factor; 'max' or 0 = as fast as possible")
    parser.add_argument("--x", type=float, help="spawn x in the map frame (m)")
    parser.add_argument("--y", type=float, help="spawn y in the map frame (m)")
    parser.add_argument("--yaw", type=float, help="spawn yaw in the map frame (rad)")
    parser.add_argument("--seed", type=int)
    parser.add_argument("--stamped", action="store_true", default=None, help="cmd_vel is TwistStamped")
    parser.add_argument("--params-file", type=Path, default=None,
                        help=f"Nav2-style parameter file (default {DEFAULT_PARAMS} if present)")
    parser.add_argument("--lockstep", action="store_true", default=None,
                        help="never run ahead of the stack: wait for the lockstep participants' reports")
    parser.add_argument("--lockstep-participants", type=_roles, metavar="ROLE,ROLE",
                        help="roles that must report before the first step (implies --lockstep)")
    add_executor_argument(parser)
    args = parser.parse_args(argv)
    params_file = _params_file(args.params_file)
    values = load_params_file(params_file) if params_file else {}
    # The node receives these values as parameter_overrides, which rclpy ranks above --ros-args; so
    # fold '--params-file' and '-p name:=value' from --ros-args in here, after the default file and
    # before the explicit flags (precedence: defaults < config file < --ros-args < flags).
    from_ros_args = _ros_args_values(ros_args)
    values.update(from_ros_args)
    if args.world is not None and not {args.x, args.y, args.yaw} - {None} \
            and not any(name.startswith("initial_pose.") for name in from_ros_args):
        values.update(_world_spawn(args.world))
    flags = {"world": args.world, "robot": args.robot, "real_time_factor": args.rtf, "seed": args.seed,
             "initial_pose.x": args.x, "initial_pose.y": args.y, "initial_pose.yaw": args.yaw,
             "enable_stamped_cmd_vel": args.stamped, "lockstep.participants": args.lockstep_participants,
             "lockstep.enabled": True if args.lockstep or args.lockstep_participants else None}
    values.update({name: coerce(name, value, "command line") for name, value in flags.items()
                   if value is not None})
    return CommandLine(values, ros_args, args.executor)


def _params_file(given: Path | None) -> Path | None:
    """``--params-file``: the user's file (else the shipped file of that name, e.g. config/x.yaml), or
    the shipped default when not given; a ValueError names the file and where it was looked for."""
    if given is None:
        return DEFAULT_PARAMS if DEFAULT_PARAMS.is_file() else None
    path = resolve(given)
    if not path.is_file():
        raise ValueError(f"--params-file: no such file: {given} ({searched(given)})")
    return path


def _ros_args_values(ros_args: list[str]) -> dict[str, ParamValue]:
    """Parameter values given after --ros-args ('--params-file FILE', '-p|--param name:=value')."""
    values: dict[str, ParamValue] = {}
    for flag, operand in itertools.pairwise(ros_args):
        if flag == "--params-file":
            values.update(load_params_file(Path(operand)))
        elif flag in ("-p", "--param"):
            name, sep, text = operand.partition(":=")
            if not sep:
                raise ValueError(f"--ros-args {flag} {operand}: expected name:=value")
            if name in defaults():  # others (use_sim_time, qos overrides...) are rclpy's business
                values[name] = coerce(name, yaml.safe_load(text), "--ros-args")
    return values


def _world_spawn(world_name: str) -> dict[str, ParamValue]:
    """The first of the world's ``spawns`` as initial_pose values; none for a world without spawns.

    Why: ``--world office_small`` alone must not put the robot at the parameter file's pose, which
    is turtlebot3_world's spawn (inside a wall elsewhere). Precedence: the --x/--y/--yaw flags and
    --ros-args initial_pose values, then the --world flag's spawn, then the parameter file.
    """
    from sim2d.core.world import load_world

    spawns = load_world(world_name).spawns
    if not spawns:
        return {}
    x, y, yaw = spawns[0]
    return {"initial_pose.x": x, "initial_pose.y": y, "initial_pose.yaw": yaw}


def _check_world_and_spawn(config: SimConfig) -> None:
    """Load the world and refuse a spawn whose footprint, at any yaw, would touch an obstacle."""
    from sim2d.core.robot import robot_model
    from sim2d.core.world import check_spawn, load_world

    world = load_world(config.node.world)
    pose = config.sim.initial_pose
    check_spawn(world, pose.x, pose.y, robot_model(config.node.robot).bounding_radius())


def main(argv: list[str] | None = None) -> int:
    """Run the simulator until interrupted; 2 on a configuration error."""
    try:
        command = parse_command_line(sys.argv[1:] if argv is None else argv)
        executor_kind(command.executor)                  # a bad $NAVSUITE_EXECUTOR fails here too
        _check_world_and_spawn(build_config(command.values))  # fail before ROS starts
    except ValueError as exc:
        print(f"sim2d: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    keep_dds_local()
    from rclpy.parameter import Parameter

    from ros_tools.runtime.runner import run_nodes
    from sim2d.ros.sim_node import Sim2dNode

    def build() -> list[Any]:
        return [Sim2dNode(parameter_overrides=[Parameter(name, value=value)
                                               for name, value in command.values.items()])]

    # The simulator is the clock, not a lockstep participant. Signals only raise the runner's flag,
    # checked between callbacks, so a Ctrl-C never lands in the middle of a stepping burst.
    try:
        return run_nodes(build, role="sim2d", rclpy_args=["sim2d", *command.ros_args],
                         executor=command.executor, lockstep=False)
    except ValueError as exc:   # e.g. a bad '-p name:=value' after --ros-args
        print(f"sim2d: error: {exc}", file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":
    sys.exit(main())
