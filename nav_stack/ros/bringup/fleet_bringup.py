"""nav-bringup for a fleet: ``--robots N`` or ``--fleet FILE``, one namespaced Nav2 stack per robot.

What runs, as Nav2 Jazzy's cloned multi-robot bringup (nav2_bringup's cloned_multi_tb3_simulation_launch)
does it:

* one ``sim2d`` with every robot (its ``fleet`` parameter): robot N's scan, odom and cmd_vel on
  ``/robotN/...``, its TF on ``/robotN/tf`` and ``/robotN/tf_static`` with unprefixed frames, one
  ``/clock``;
* per robot a full stack in ``/robotN``: map_server and AMCL (Jazzy runs one per namespace, so each
  robot loads the map itself), both lifecycle managers, planner, controller, behaviors, navigator,
  waypoint follower and whatever the parameter files add; processes ``robotN/nav2`` (or
  ``robotN/localization`` and ``robotN/navigation`` with ``--isolated``), and ``robotN/initial_pose``;
* the parameter files are Nav2's multi-robot kind: one set for every robot (``--params``, e.g. Jazzy's
  ``nav2_multirobot_params_all.yaml``), rewritten per robot (nav_stack/ros/bringup/namespaced_params.py).
  Without ``--params`` each robot gets its model's own file (nav_stack/ros/bringup/robot_params.py) and
  config/fleet/robot_namespace_overlay.yaml, which moves its lidar topic into the namespace.

The robots' stacks start side by side (none waits for another's readiness) and lockstep holds the
simulator until every one of them has reported (roles ``robotN/nav2``...), for up to the readiness
timeout. ``--robots N`` names them ``robot1`` .. ``robotN`` (Nav2's names), of the ``--robot`` model,
at the world's spawns and then on free space next to the first one (nav_stack/core/fleet_spawns.py).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from nav_stack.core.fleet_spec import (
    FleetMember,
    FleetSpecError,
    load_fleet_file,
    numbered_fleet,
    sim_fleet_entries,
)
from nav_stack.ros.bringup.bringup_components import COMPONENT_READY, component_role
from nav_stack.ros.bringup.robot_params import ROBOTS, params_for_robot
from navsuite_data import config_path, resolve, searched

NAMESPACE_OVERLAY = config_path("fleet/robot_namespace_overlay.yaml")


def add_fleet_arguments(parser: argparse.ArgumentParser) -> None:
    """``--robots N`` and ``--fleet FILE``."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--robots", type=int, default=None, metavar="N",
                       help="a fleet of N robots of the --robot model (robot1..robotN), each with its own "
                            "namespaced stack, at the world's spawns and then on free space nearby")
    group.add_argument("--fleet", default=None, metavar="FILE",
                       help="a fleet from a YAML list of {name, model, x, y, yaw} "
                            "(model defaults to --robot)")


def is_fleet(args: argparse.Namespace) -> bool:
    """Whether the command line asks for a fleet."""
    return bool(getattr(args, "members", ()))


def refuse_one_robot_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Exit 2 when a fleet is asked for with options that place or map with one robot (before the
    world's defaults fill ``--x/--y/--yaw``)."""
    if args.robots is None and args.fleet is None:
        return
    if args.slam:
        parser.error("--slam maps with one robot: a fleet localizes on a map (drop --slam)")
    if any(getattr(args, name) is not None for name in ("x", "y", "yaw")):
        parser.error("--x/--y/--yaw place one robot: give a fleet's poses in a --fleet file")


def resolve_fleet(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Set ``args.members`` (the fleet's robots, () for one robot); exit 2 with a message on a bad fleet.

    Runs once the world's defaults are known (``args.world``); the first robot's spawn then replaces
    ``--x/--y/--yaw``, which the simulator's own spawn check reads.
    """
    args.members = ()
    if args.robots is None and args.fleet is None:
        return
    try:
        if args.fleet is not None:
            path = resolve(args.fleet)
            if not path.is_file():
                parser.error(f"--fleet: no such file: {args.fleet} ({searched(args.fleet)})")
            args.members = load_fleet_file(path, ROBOTS, args.robot)
        else:
            args.members = numbered_fleet(args.robot, default_spawns(args.world, args.robots))
    except FleetSpecError as error:
        parser.error(f"{'--fleet' if args.fleet is not None else '--robots'}: {error}")
    first = args.members[0]
    args.x, args.y, args.yaw = first.pose  # what the single-robot parts (sim2d's own check) read


def default_spawns(world: str, count: int) -> list[tuple[float, float, float]]:
    """``count`` spawn poses in ``world``: its spawns, then free map cells near the first."""
    from nav_stack.core.fleet_spawns import SPAWN_CLEARANCE, free_positions, spread_spawns
    from nav_stack.core.map_io import MapLoadError, load_map
    from nav_stack.ros.bringup.world_defaults import world_defaults

    defaults = world_defaults(world)
    free = None
    if defaults.map_yaml is not None:
        try:
            free = free_positions(load_map(defaults.map_yaml), SPAWN_CLEARANCE)
        except (MapLoadError, OSError):
            free = None  # map_server reports a broken map with its own message
    return spread_spawns(count, defaults.spawns or (defaults.spawn,), free)


def robot_params(args: argparse.Namespace, member: FleetMember) -> list[str]:
    """The parameter files of one robot: the user's (every robot the same), else its model's own file
    with the namespace overlay."""
    if args.own_params:
        return list(args.params)
    return [str(params_for_robot(member.model)), str(NAMESPACE_OVERLAY)]


def check_fleet_params(args: argparse.Namespace) -> str | None:
    """Why the fleet's parameter files cannot run (None: they can); warns on stderr about topic settings
    outside a robot's namespace (they read or feed no robot)."""
    from nav_stack.ros.bringup.bringup_plan import OWNED_SECTIONS, plan_bringup
    from nav_stack.ros.bringup.config_check import ConfigError
    from nav_stack.ros.bringup.namespaced_params import foreign_topics, robot_namespace
    from nav_stack.ros.bringup.param_files import ParamFileError

    checked: set[tuple[str, ...]] = set()
    for member in args.members:
        files = tuple(robot_params(args, member))
        if files in checked:
            continue
        checked.add(files)
        try:
            plan = plan_bringup(files)
            running = {*plan.localization.node_names, *plan.navigation.node_names, *OWNED_SECTIONS}
            for setting in foreign_topics(files, robot_namespace(member.name), running):
                print(f"nav-bringup: warning: {setting} is outside the robot's namespace: no robot's topic "
                      f"(write <robot_namespace>/... or a relative name)", file=sys.stderr, flush=True)
        except (ConfigError, ParamFileError) as error:
            return str(error)
    return None


def _python_module(module: str, *args: str) -> list[str]:
    return [sys.executable, "-m", module, *args]


def fleet_process_specs(args: argparse.Namespace, stamped: bool, respawn_delay: float) -> list[Any]:
    """The ProcessSpecs of a fleet launch, in start order: sim2d, then every robot's processes."""
    from nav_stack.ros.bringup.namespaced_params import namespace_remaps, robot_namespace
    from ros_tools.launch import ProcessSpec

    members: Sequence[FleetMember] = args.members
    components = ["localization", "navigation"] if args.isolated else ["all"]
    map_args = ["--map", str(Path(args.map).resolve())] if args.map else []
    specs: list[ProcessSpec] = []
    if not args.no_sim:
        roles = [component_role(c, m.name) for m in members for c in components] + list(args.participant)
        lockstep = ["--lockstep-participants", ",".join(roles)] if args.lockstep else []
        fleet = ",".join(f'"{entry}"' for entry in sim_fleet_entries(members))
        first = members[0]
        sim_params = ["--params-file", str(Path(args.sim_params).resolve())] if args.sim_params else []
        specs.append(ProcessSpec("sim2d", _python_module(
            "sim2d.ros.cli", "--world", args.world, "--robot", first.model, "--rtf", args.rtf,
            "--x", repr(first.x), "--y", repr(first.y), "--yaw", repr(first.yaw), *lockstep,
            *(["--stamped"] if stamped else []), "--ros-args", *sim_params, "-p", f"fleet:=[{fleet}]",
            # every robot's stack starts before the first step: wait as long as a stack may take
            "-p", f"lockstep.startup_timeout:={float(args.ready_timeout)}"),
            ready=r"sim2d", ready_timeout=60.0))

    def component(name: str, member: FleetMember) -> ProcessSpec:
        params = [arg for path in robot_params(args, member)
                  for arg in ("--params", str(Path(path).resolve()))]
        return ProcessSpec(component_role(name, member.name), _python_module(
            "nav_stack.ros.bringup.nav_bringup", "component", name, "--namespace", member.name, *params,
            *map_args,
            *(["--stamped-cmd-vel"] if stamped else [])),
            ready=COMPONENT_READY.format(name=name), ready_timeout=args.ready_timeout,
            respawn=args.respawn, respawn_delay=respawn_delay, ready_before_next=False)

    def initial_pose(member: FleetMember) -> ProcessSpec:
        remaps = [arg for rule in [f"__ns:={robot_namespace(member.name)}",
                                   *namespace_remaps(robot_namespace(member.name))] for arg in ("-r", rule)]
        return ProcessSpec(f"{member.name}/initial_pose", _python_module(
            "nav_stack.ros.localization.initial_pose_publisher", "--ros-args", *remaps,
            "-p", "use_sim_time:=true",
            "-p", f"x:={member.x!r}", "-p", f"y:={member.y!r}", "-p", f"yaw:={member.yaw!r}",
            "-p", f"resend_after_restart:={'true' if args.respawn else 'false'}"),
            ready="AMCL confirmed the initial pose" if args.isolated else None,
            ready_timeout=args.ready_timeout, required=False, ready_before_next=False)

    publishers = [initial_pose(member) for member in members] if args.initial_pose else []
    if args.isolated:  # as one robot's: localization, the initial pose, then navigation
        return [*specs, *(component("localization", m) for m in members), *publishers,
                *(component("navigation", m) for m in members)]
    return [*specs, *publishers, *(component("all", m) for m in members)]
