"""Command line: ``sim2d --world turtlebot3_world --robot waffle --rtf 5 --x -2.0 --y -0.5 --yaw 0``.

Parameters come from config/sim2d.yaml (Nav2 layout ``sim2d: ros__parameters:``; ``--params-file``
picks another), then the flags override them; anything after ``--ros-args`` goes to rclpy (remaps,
``-p name:=value``). The whole configuration, including the world file, is validated before ROS
starts: a bad flag, parameter file or world gives one line ``sim2d: error: <file>: <field>: ...``
and exit code 2.
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
from pathlib import Path
from typing import NoReturn

import yaml

from sim2d.ros.config import ParamValue, build_config, coerce, defaults, load_params_file

DEFAULT_PARAMS = Path(__file__).resolve().parents[2] / "config" / "sim2d.yaml"
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


def parse(argv: list[str]) -> tuple[dict[str, ParamValue], list[str]]:
    """Parameter values (file, then flags) and the rclpy arguments of a command line."""
    ros_args: list[str] = []
    if "--ros-args" in argv:
        split = argv.index("--ros-args")
        argv, ros_args = argv[:split], argv[split:]
    parser = _Parser(prog="sim2d", description="2D TurtleBot3 simulator on the ROS 2 graph.")
    parser.add_argument("--world", help="world name (sim2d/worlds/) or world/map_server YAML path")
    parser.add_argument("--robot", choices=("waffle", "burger"))
    parser.add_argument("--rtf", type=_rtf, help="real-time factor; 'max' or 0 = as fast as possible")
    parser.add_argument("--x", type=float, help="spawn x in the map frame (m)")
    parser.add_argument("--y", type=float, help="spawn y in the map frame (m)")
    parser.add_argument("--yaw", type=float, help="spawn yaw in the map frame (rad)")
    parser.add_argument("--seed", type=int)
    parser.add_argument("--stamped", action="store_true", default=None, help="cmd_vel is TwistStamped")
    parser.add_argument("--params-file", type=Path, default=None,
                        help=f"Nav2-style parameter file (default {DEFAULT_PARAMS} if present)")
    args = parser.parse_args(argv)
    params_file = args.params_file or (DEFAULT_PARAMS if DEFAULT_PARAMS.is_file() else None)
    values = load_params_file(params_file) if params_file else {}
    # The node receives these values as parameter_overrides, which rclpy ranks above --ros-args; so
    # fold '--params-file' and '-p name:=value' from --ros-args in here, after the default file and
    # before the explicit flags (precedence: defaults < config file < --ros-args < flags).
    values.update(_ros_args_values(ros_args))
    flags = {"world": args.world, "robot": args.robot, "real_time_factor": args.rtf, "seed": args.seed,
             "initial_pose.x": args.x, "initial_pose.y": args.y, "initial_pose.yaw": args.yaw,
             "enable_stamped_cmd_vel": args.stamped}
    values.update({name: coerce(name, value, "command line") for name, value in flags.items()
                   if value is not None})
    return values, ros_args


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


def main(argv: list[str] | None = None) -> int:
    """Run the simulator until interrupted; 2 on a configuration error."""
    try:
        values, ros_args = parse(sys.argv[1:] if argv is None else argv)
        from sim2d.core.world import load_world

        load_world(build_config(values).node.world)      # fail before ROS starts
    except ValueError as exc:
        print(f"sim2d: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from rclpy.parameter import Parameter

    from sim2d.ros.sim_node import Sim2dNode

    rclpy.init(args=["sim2d", *ros_args])
    node = None
    try:
        node = Sim2dNode(parameter_overrides=[Parameter(name, value=value) for name, value in values.items()])
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        executor.spin()
    except ValueError as exc:   # e.g. a bad '-p name:=value' after --ros-args
        print(f"sim2d: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        if rclpy.ok():
            rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
