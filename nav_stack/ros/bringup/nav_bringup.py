"""nav-bringup: the simulator and the whole Nav2-style stack in one command (instead of the seeds' terminals).

    nav-bringup [--world turtlebot3_world] [--robot waffle|burger|tb4] [--map maps/<world>.yaml]
                [--params (the robot's: config/nav2_params.yaml or nav2_params_tb4.yaml)] [--rtf 1.0]
                [--no-sim] [--isolated]
                [--no-lockstep] [--no-respawn] [--executor events|single]
                [--no-initial-pose] [--x X --y Y --yaw YAW (default: the world's first spawn)]
                [--robots N | --fleet FILE]
                [--verbose] [--log-dir artifacts/logs]

Processes, started in order by ros_tools.launch.Launcher, each waiting for the previous one's
readiness line (all with use_sim_time true; sim2d publishes /clock):

1. ``sim2d`` (python -m sim2d.ros.cli) — ready when it logs its first status line;
2. ``nav2``: every Nav2 node in one process on one executor, as Nav2's ``use_composition``:
   map_server, amcl, lifecycle_manager_localization, planner_server + global_costmap,
   controller_server + local_costmap, behavior_server, bt_navigator, waypoint_follower,
   lifecycle_manager_navigation — ready when both managers are active;
3. ``initial_pose`` (amcl_init_pose_publisher): publishes the seeds' initial pose until AMCL
   confirms it, then exits (not required: its exit does not end the launch).

``--isolated`` runs localization and navigation as two processes instead (``localization`` before
``initial_pose``, then ``navigation``); ``NAVSUITE_LAYOUT=isolated`` in the environment makes that the
default, so that every command and test that starts nav-bringup (the demos, the system tests) can be
run in that layout without changing them (``--slam`` ignores it: it always runs separate processes).

Then it prints exactly ``Nav2 is ready``. Respawn (default; ``--no-respawn`` turns it off), as
nav2_bringup's ``use_respawn``: a node process that dies is started again with the same command and
parameters after RESPAWN_DELAY s (ros_tools.launch's ``respawn``); its lifecycle managers start it up
again (autostart), or, for a node whose manager lives on, the manager's bond brings the system back
(``attempt_respawn_reconnection``). The initial-pose publisher then stays up and gives a restarted AMCL
its last pose (nav_stack/ros/localization/initial_pose_publisher.py says why). A node process that
dies more than ``respawn_max_deaths`` times in a row is given up, and the launch ends. The simulator is never
respawned: a new one cannot restore the world (the robot's pose, spawned obstacles, the battery), so
its death ends the launch at once, naming it. Without respawn, a process that dies ends the launch
with its exit code (and its last lines are shown); Ctrl-C stops everything in reverse order. The
simulator stays a separate process (nav_stack never imports sim2d). The console shows readiness,
warnings and errors; each process's full log is in ``--log-dir`` (``--verbose`` streams it all).

Lockstep (default; ``--no-lockstep`` turns it off): sim2d waits for the node processes (roles
``nav2``, or ``localization`` and ``navigation``) before its first step and never runs more than
one control period ahead of them, so ``--rtf`` is an upper bound and the outcome does not depend on
the machine's load. In lockstep with the simulator, velocity commands are stamped on both sides
(sim2d ``--stamped``; ``enable_stamped_cmd_vel: true`` for every command producer the files run,
whatever they say): sim2d applies each at its stamp + ``stamped_cmd_vel_delay``, so when it takes
effect does not depend on when it crossed DDS (docs/architecture.md, "What repeats").
``--unstamped-cmd-vel`` keeps the files' setting and a Twist simulator.
``python -m nav_stack.ros.bringup.nav_bringup component <name> ...`` is the entry point of
the node processes (nav_stack/ros/bringup/bringup_components.py).

``--robots N`` or ``--fleet FILE`` launches a fleet instead: one simulator with every robot and one
namespaced stack per robot (nav_stack/ros/bringup/fleet_bringup.py; docs/fleet.md).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from nav_stack.ros.bringup.bringup_components import (
    COMPONENT_READY,
    COMPONENTS,
    component_role,
    run_component,
)
from nav_stack.ros.bringup.fleet_bringup import (
    add_fleet_arguments,
    check_fleet_params,
    fleet_process_specs,
    is_fleet,
    refuse_one_robot_options,
    resolve_fleet,
)
from nav_stack.ros.bringup.robot_params import ROBOTS, params_for_robot
from navsuite_data import data_root, resolve, searched
from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument

#: The folder holding the shipped config/ and maps/ (the repository in a checkout, the installed
#: navsuite_data package otherwise): ``config/nav2_params.yaml`` means the same file below both.
REPO = data_root()
DEFAULT_PARAMS = params_for_robot("waffle")
READY_LINE = "Nav2 is ready"
RESPAWN_DELAY = 2.0  # s (wall) before a dead node process starts again: nav2_bringup's respawn_delay
SIM_NOT_RESPAWNED = ("the simulator is not respawned: a new one cannot restore the world (robot pose, "
                     "obstacles, battery)")


def _python_module(module: str, *args: str) -> list[str]:
    return [sys.executable, "-m", module, *args]


# ------------------------------------------------------------------ launch
#: Environment variable naming the default process layout (``one-process`` or ``isolated``).
LAYOUT_ENV = "NAVSUITE_LAYOUT"

def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="nav-bringup", description=__doc__.split("\n\n")[0])
    parser.add_argument("--world", default=None,
                        help="sim2d world name or YAML (default turtlebot3_world); also sets the default "
                             "--map (maps/<world>.yaml) and spawn (the world's first spawn)")
    parser.add_argument("--robot", default="waffle", choices=ROBOTS,
                        help="the simulated robot; also picks the default --params")
    parser.add_argument("--map", default=None,
                        help="map_server YAML (default: the --world's map, else from --params)")
    parser.add_argument("--params", action="append", default=None, metavar="FILE",
                        help="Nav2 parameter file, e.g. Nav2's own nav2_params.yaml (default: the --robot's, "
                             "nav_stack.ros.bringup.robot_params); repeat it to apply overlays, "
                             "later files winning")
    parser.add_argument("--sim-params", default=None,
                        help="sim2d parameter file applied over config/sim2d.yaml (e.g. "
                             "config/sim2d_battery_patrol.yaml)")
    parser.add_argument("--rtf", default="1.0", help="sim real-time factor ('max' = fastest)")
    parser.add_argument("--x", type=float, default=None, help="spawn and initial pose x (m)")
    parser.add_argument("--y", type=float, default=None, help="spawn and initial pose y (m)")
    parser.add_argument("--yaw", type=float, default=None, help="spawn and initial pose yaw (rad)")
    parser.add_argument("--no-sim", action="store_true", help="only the stack (a sim runs elsewhere)")
    parser.add_argument("--slam", action="store_true",
                        help="map with SLAM (slam + map_saver) instead of map_server + AMCL")
    parser.add_argument("--isolated", action="store_true", default=None,
                        help=f"localization and navigation as two processes (default: one, or "
                             f"${LAYOUT_ENV}=isolated)")
    parser.add_argument("--no-lockstep", dest="lockstep", action="store_false", default=True,
                        help="let the simulator run by the wall clock alone (default: lockstep)")
    parser.add_argument("--unstamped-cmd-vel", dest="stamped_cmd_vel", action="store_false", default=True,
                        help="in lockstep, keep the parameter files' enable_stamped_cmd_vel and a Twist "
                             "simulator (default: stamped commands on both sides, so runs repeat)")
    parser.add_argument("--participant", action="append", default=[], metavar="ROLE",
                        help="one more lockstep role the simulator waits for before its first step "
                             "(e.g. a state machine's name); repeatable")
    parser.add_argument("--respawn", dest="respawn", action="store_true", default=True,
                        help="start a node process that died again, as nav2_bringup's use_respawn (default)")
    parser.add_argument("--no-respawn", dest="respawn", action="store_false",
                        help="a node process that dies ends the launch")
    add_executor_argument(parser)
    parser.add_argument("--initial-pose", dest="initial_pose", action="store_true", default=True,
                        help="publish the initial pose until AMCL confirms it (default)")
    parser.add_argument("--no-initial-pose", dest="initial_pose", action="store_false")
    parser.add_argument("--headless", action="store_true", default=True, help="no GUI (the only mode)")
    parser.add_argument("--ready-timeout", type=float, default=120.0, help="s (wall) each process may take")
    parser.add_argument("--verbose", action="store_true",
                        help="stream every line of every process (default: readiness, warnings and errors)")
    parser.add_argument("--log-dir", type=Path, default=None,
                        help="where each process's full log goes, as <process>.log (default: "
                             "$NAVSUITE_LOG_DIR, else artifacts/logs)")
    add_fleet_arguments(parser)
    return parser


def _named_map(files: Sequence[str]) -> str:
    """map_server's ``yaml_filename`` in the parameter files, "" when they set none (Nav2's own file
    leaves it empty: nav2_bringup's ``map`` launch argument fills it). A file that does not parse
    counts as naming none here; the parameter check reports it."""
    from nav_stack.ros.bringup.param_files import NavParams, ParamFileError

    try:
        return str(NavParams([Path(f) for f in files]).get("map_server", "yaml_filename") or "")
    except (ParamFileError, OSError):
        return ""


def _apply_world_defaults(args: argparse.Namespace, own_params: bool) -> None:
    """Fill --world, --map and the spawn the user left out from the world
    (nav_stack.ros.bringup.world_defaults).

    The world's map (an absolute path) replaces the parameter file's ``yaml_filename`` when the user
    chose the world, left --params to the robot's shipped file (its relative
    ``maps/turtlebot3_world.yaml`` would only load when started from the repository), or gave files
    that name no map, as Nav2's own file does (nav2_bringup passes its ``map`` argument then). A
    relative ``yaml_filename`` that is not there from the working directory means the shipped map of
    that name (navsuite_data.resolve), so a shipped parameter file given as --params works anywhere.
    """
    from nav_stack.ros.bringup.world_defaults import world_defaults

    chosen, args.world = args.world is not None, args.world or "turtlebot3_world"
    defaults = world_defaults(args.world)
    named = _named_map(args.params)
    wants_map = chosen or not own_params or not named
    if wants_map and args.map is None and not args.slam and defaults.map_yaml is not None:
        args.map = str(defaults.map_yaml)
    elif args.map is None and not args.slam and named and not Path(named).exists():
        shipped_map = resolve(named)
        if shipped_map.is_file():
            args.map = str(shipped_map)
    for name, value in zip(("x", "y", "yaw"), defaults.spawn, strict=True):
        if getattr(args, name) is None:
            setattr(args, name, value)


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    """The launch options: parsed, checked (exit 2 with a message) and completed by the world's defaults."""
    parser = _parser()
    args = parser.parse_args(list(argv))
    args.own_params = own_params = args.params is not None
    args.params = args.params or [str(params_for_robot(args.robot))]
    _validate(args, parser)
    if args.isolated is None:
        args.isolated = _layout_is_isolated(parser) and not args.slam
    refuse_one_robot_options(args, parser)
    _apply_world_defaults(args, own_params)
    resolve_fleet(args, parser)
    return args


def _layout_is_isolated(parser: argparse.ArgumentParser) -> bool:
    """The default layout from $NAVSUITE_LAYOUT: ``one-process`` (or unset) or ``isolated``."""
    layout = os.environ.get(LAYOUT_ENV, "one-process").strip().lower() or "one-process"
    if layout not in ("one-process", "isolated"):
        parser.error(f"${LAYOUT_ENV}={layout!r}: use 'one-process' or 'isolated'")
    return layout == "isolated"


def _validate(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    if args.slam and args.map is not None:
        parser.error("--slam builds its own map: drop --map (or drop --slam to localize on a map)")
    if args.slam and args.isolated:
        parser.error("--slam always runs its nodes as separate processes: drop --isolated")
    args.params = [_existing_file(parser, "--params", path) for path in args.params]
    if args.map is not None:
        args.map = _existing_file(parser, "--map", args.map)
    if args.sim_params is not None:
        args.sim_params = _existing_file(parser, "--sim-params", args.sim_params)
    if args.rtf.lower() not in ("max", "inf"):
        try:
            if float(args.rtf) <= 0.0:
                raise ValueError
        except ValueError:
            parser.error(f"--rtf must be a positive number or 'max', got {args.rtf!r}")


def _existing_file(parser: argparse.ArgumentParser, option: str, text: str) -> str:
    """A file option's path: the user's (absolute, or relative to the working directory), else the
    shipped file of that name (``config/...``, ``maps/...``: navsuite_data), so the documented commands
    also run outside a checkout; exit 2 naming the file and where it was looked for."""
    path = resolve(text)
    if not path.is_file():
        parser.error(f"{option}: no such file: {text} ({searched(text)})")
    return str(path)


def check_params(args: argparse.Namespace) -> str | None:
    """Why the parameter files cannot run on this stack (every problem, one message), or None.

    Runs before any process starts, so a file naming a plugin or a server this stack lacks is refused
    within a second instead of failing a node's configure later, one problem at a time.
    """
    from nav_stack.ros.bringup.bringup_plan import plan_bringup
    from nav_stack.ros.bringup.config_check import ConfigError
    from nav_stack.ros.bringup.param_files import ParamFileError

    if is_fleet(args):
        return check_fleet_params(args)
    try:
        plan_bringup(args.params, slam=args.slam)
    except (ConfigError, ParamFileError) as error:
        return str(error)
    return None


def process_specs(args: argparse.Namespace) -> list[Any]:
    """The ProcessSpecs of a launch, in start order."""
    from ros_tools.launch import ProcessSpec

    if is_fleet(args):
        return fleet_process_specs(args, stamps_cmd_vel(args), RESPAWN_DELAY)
    params = [str(Path(p).resolve()) for p in args.params]
    param_args = [arg for path in params for arg in ("--params", path)]
    map_args = ["--map", str(Path(args.map).resolve())] if args.map else []
    specs: list[ProcessSpec] = []
    components = ["navigation"] if args.slam else ["localization", "navigation"] if args.isolated else ["all"]
    stamped = stamps_cmd_vel(args)
    if not args.no_sim:
        roles = [component_role(c) for c in components] + list(args.participant)
        lockstep = ["--lockstep-participants", ",".join(roles)] if args.lockstep else []
        specs.append(ProcessSpec("sim2d", _python_module(
            "sim2d.ros.cli", "--world", args.world, "--robot", args.robot, "--rtf", args.rtf,
            "--x", str(args.x), "--y", str(args.y), "--yaw", str(args.yaw), *lockstep,
            *(["--stamped"] if stamped else []),
            *(["--ros-args", "--params-file", str(Path(args.sim_params).resolve())] if args.sim_params
              else [])),
            ready=r"sim2d", ready_timeout=60.0))

    def component(name: str) -> ProcessSpec:
        slam = ["--map-from-slam"] if args.slam else []
        return ProcessSpec(component_role(name), _python_module(
            "nav_stack.ros.bringup.nav_bringup", "component", name, *param_args, *map_args, *slam,
            *(["--stamped-cmd-vel"] if stamped else [])),
            ready=COMPONENT_READY.format(name=name), ready_timeout=args.ready_timeout,
            respawn=args.respawn, respawn_delay=RESPAWN_DELAY)

    initial_pose = ProcessSpec("initial_pose", _python_module(
        "nav_stack.ros.localization.initial_pose_publisher", "--ros-args", "-p", "use_sim_time:=true",
        "-p", f"x:={args.x}", "-p", f"y:={args.y}", "-p", f"yaw:={args.yaw}",
        "-p", f"resend_after_restart:={'true' if args.respawn else 'false'}"),
        ready="AMCL confirmed the initial pose", ready_timeout=args.ready_timeout, required=False)
    if args.slam:  # Nav2's "navigation with SLAM": slam + map_saver instead of map_server + amcl
        from nav_stack.ros.slam.slam_bringup import slam_processes

        start = f"map_start_pose:=[{args.x}, {args.y}, {args.yaw}]"  # SLAM's map frame = the world's
        specs.extend(slam_processes(params, extra_ros_args=["-p", start], ready_timeout=args.ready_timeout))
        specs.append(component("navigation"))
    elif args.isolated:
        specs.append(component("localization"))
        if args.initial_pose:
            specs.append(initial_pose)
        specs.append(component("navigation"))
    else:
        if args.initial_pose:
            initial_pose.ready = None  # AMCL starts in the same process as the navigation nodes
            specs.append(initial_pose)
        specs.append(component("all"))
    if args.executor:
        for spec in specs:
            spec.env["NAVSUITE_EXECUTOR"] = args.executor
    return specs


def stamps_cmd_vel(args: argparse.Namespace) -> bool:
    """Whether this launch stamps velocity commands: in lockstep with its own simulator, unless
    ``--unstamped-cmd-vel`` (exactness is promised only there; wall-clock runs keep the files' type)."""
    return bool(args.lockstep and not args.no_sim and args.stamped_cmd_vel)


def launch(args: argparse.Namespace, output: Callable[[str], None] | None = None) -> int:
    """Start the specs, print READY_LINE, supervise; the launch's exit code (Launcher.run semantics)."""
    from ros_tools.launch import Launcher, LaunchError, default_log_dir, show_problems

    log_dir = args.log_dir or default_log_dir()
    launcher = Launcher(output=output, log_dir=log_dir, show=None if args.verbose else show_problems)
    if not args.verbose:
        launcher.log(f"every process logs to {log_dir}/<process>.log; --verbose shows it all here")
    with launcher.stopping_on_signals() as interrupted:
        try:
            launcher.start(process_specs(args))
            (output or (lambda line: print(line, flush=True)))(READY_LINE)
            code = launcher.wait()
            _name_a_dead_simulator(launcher)
        except LaunchError as error:
            launcher.log(f"ERROR: {error}")
            code = 1
        finally:
            launcher.log("shutting down")
            launcher.shutdown()
    if interrupted.is_set():
        return 130 if code == 0 else code
    return code


def _name_a_dead_simulator(launcher: Any) -> None:
    """Say why the launch ends when the simulator died (it has no respawn, unlike the node processes)."""
    for running in launcher.running:
        if running.spec.name == "sim2d" and running.proc.poll() is not None:
            launcher.log(f"ERROR: sim2d died: {SIM_NOT_RESPAWNED}; ending the run")


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry ``nav-bringup``; ``component <name>`` runs one node process."""
    argv = list(sys.argv[1:] if argv is None else argv)
    keep_dds_local()
    if argv[:1] == ["component"]:
        sub = argparse.ArgumentParser(prog="nav-bringup component")
        sub.add_argument("name", choices=COMPONENTS)
        sub.add_argument("--params", action="append", default=None, metavar="FILE")
        sub.add_argument("--map", default=None)
        sub.add_argument("--map-from-slam", action="store_true",
                         help="the map comes from SLAM: do not hold the simulator until it arrives")
        sub.add_argument("--stamped-cmd-vel", action="store_true",
                         help="enable_stamped_cmd_vel: true for every velocity command producer it runs")
        sub.add_argument("--namespace", default="",
                         help="a fleet robot's name: every node under /<name> "
                              "(nav_stack/ros/bringup/fleet_bringup.py)")
        add_executor_argument(sub)
        opts = sub.parse_args(argv[1:])
        return run_component(opts.name, opts.params or [str(DEFAULT_PARAMS)], opts.map, opts.executor,
                             opts.map_from_slam, opts.stamped_cmd_vel, opts.namespace)
    args = parse_args(argv)
    problem = check_params(args)
    if problem:
        print(f"nav-bringup: {problem}", file=sys.stderr, flush=True)
        return 2
    return launch(args)


if __name__ == "__main__":
    raise SystemExit(main())
