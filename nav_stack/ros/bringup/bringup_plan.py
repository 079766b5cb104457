"""What nav-bringup runs for a set of Nav2 parameter files: the lifecycle lists and the cmd_vel chain.

Why: Nav2 keeps the lifecycle managers' ``node_names`` and ``autostart`` in its launch files, not in
``nav2_params.yaml``, so a Nav2 user's file has no such sections. nav-bringup therefore plays the
part of nav2_bringup's launch files:

* **Lifecycle lists**: localization ``[map_server, amcl]``; navigation Jazzy's list
  (plugin_catalog.NAVIGATION_NODES), without the optional servers (smoother, velocity smoother,
  collision monitor, docking) that the files do not configure. ``autostart`` is true. A file's
  own ``lifecycle_manager_*`` section overrides both, as a launch argument would in Nav2.
* **The velocity chain**, by remapping as Nav2's launch does: controller_server and behavior_server
  publish ``cmd_vel`` remapped to ``cmd_vel_nav``; velocity_smoother reads ``cmd_vel_nav`` and
  publishes ``cmd_vel_smoothed``; collision_monitor reads its ``cmd_vel_in_topic`` and publishes
  ``cmd_vel``. When one of the two filters is left out, the chain closes around it, so the robot
  always receives ``cmd_vel``. docking_server publishes ``cmd_vel`` directly: its last centimetres
  end in contact with the dock, which the collision monitor exists to prevent.
* **Checks**: every plugin type and every server the files ask for must exist in this stack
  (config_check); all problems are raised together in one ConfigError.

Pure: no rclpy. The remaps are rcl's node-scoped rules (``-r <node>:<from>:=<to>``), given to every
node process of the launch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from nav_stack.ros.bringup.config_check import ConfigError, Problem, check_node_names, check_plugins
from nav_stack.ros.bringup.param_files import NavParams
from nav_stack.ros.bringup.plugin_catalog import (
    AVAILABLE_NODES,
    LOCALIZATION_NODES,
    NAVIGATION_NODES,
    NOT_LAUNCHED,
    OPTIONAL_NODES,
)

LOCALIZATION_MANAGER = "lifecycle_manager_localization"
NAVIGATION_MANAGER = "lifecycle_manager_navigation"
#: s: the managers' bond_timeout unless a file sets it. Not nav2_bringup's (Nav2's default is 4 s):
#: bond heartbeats run on the wall clock, and a loaded two-core CI machine stalled a process past 4 s.
BOND_TIMEOUT = 10.0
#: Nodes that publish velocity commands into the chain (Nav2's launch remaps their cmd_vel).
CMD_VEL_PRODUCERS = ("controller_server", "behavior_server")
#: Costmap and helper sections that belong to a server rather than being servers themselves.
OWNED_SECTIONS = ("local_costmap/local_costmap", "global_costmap/global_costmap")


@dataclass(frozen=True)
class ManagerPlan:
    """One lifecycle manager: the nodes it brings up, in order, and whether it starts by itself."""

    name: str
    node_names: tuple[str, ...]
    autostart: bool


@dataclass(frozen=True)
class BringupPlan:
    """Everything bringup decides from the parameter files."""

    localization: ManagerPlan
    navigation: ManagerPlan
    remaps: tuple[str, ...]  # rcl remap rules, node-scoped
    notes: tuple[str, ...]  # sections left alone, for the log

    def ros_args(self) -> list[str]:
        """The remaps as ``--ros-args`` arguments (``-r rule`` each)."""
        return [arg for rule in self.remaps for arg in ("-r", rule)]


def _manager(params: NavParams, name: str, default: Sequence[str]) -> tuple[ManagerPlan, list[Problem]]:
    names = params.get(name, "node_names")
    listed = tuple(str(n) for n in (default if names is None else names))
    autostart = bool(params.get(name, "autostart", True))
    return ManagerPlan(name, listed, autostart), check_node_names(params, name, listed)


def _default_navigation(params: NavParams) -> tuple[str, ...]:
    return tuple(n for n in NAVIGATION_NODES if n not in OPTIONAL_NODES or params.configures(n))


def cmd_vel_remaps(nodes: Sequence[str], params: NavParams) -> tuple[str, ...]:
    """The remap rules that chain the producers through the filters in ``nodes`` to ``cmd_vel``."""
    smoother, monitor = "velocity_smoother" in nodes, "collision_monitor" in nodes
    monitor_in = str(params.get("collision_monitor", "cmd_vel_in_topic", "cmd_vel_smoothed"))
    rules: list[str] = []
    if smoother:
        first = "cmd_vel_nav"
        rules.append("velocity_smoother:cmd_vel:=cmd_vel_nav")
        output = monitor_in if monitor else "cmd_vel"
        if output != "cmd_vel_smoothed":
            rules.append(f"velocity_smoother:cmd_vel_smoothed:={output}")
    elif monitor:
        first = monitor_in
    else:
        return ()
    rules.extend(f"{node}:cmd_vel:={first}" for node in CMD_VEL_PRODUCERS if node in nodes)
    return tuple(rules)


def _notes(params: NavParams, running: set[str]) -> list[str]:
    notes = []
    for node in params.nodes:
        base = node.rsplit("/", 1)[-1]
        if node in running or node in OWNED_SECTIONS or base.startswith("lifecycle_manager"):
            continue
        if base in NOT_LAUNCHED:
            notes.append(f"{node}: not started by nav-bringup ({NOT_LAUNCHED[base]})")
        elif base in AVAILABLE_NODES or base in NAVIGATION_NODES:
            notes.append(f"{node}: configured, but no lifecycle manager lists it; not started")
        else:
            notes.append(f"{node}: not a node of this stack; its section is left to whoever runs it")
    return notes


def plan_bringup(files: Sequence[Path | str], slam: bool = False) -> BringupPlan:
    """The plan for ``files`` (merged in order); ConfigError lists every setting the stack cannot run.

    With ``slam`` the localization manager is not run (SLAM replaces map_server and AMCL).
    """
    params = NavParams(files)
    localization, problems = _manager(params, LOCALIZATION_MANAGER, LOCALIZATION_NODES)
    if slam:
        localization, problems = ManagerPlan(LOCALIZATION_MANAGER, (), True), []
    navigation, more = _manager(params, NAVIGATION_MANAGER, _default_navigation(params))
    problems += more
    running = set(localization.node_names) | set(navigation.node_names)
    problems += check_plugins(params, [n for n in running if n in AVAILABLE_NODES])
    if problems:
        raise ConfigError(params.files, problems)
    return BringupPlan(localization, navigation, cmd_vel_remaps(navigation.node_names, params),
                       tuple(_notes(params, running)))
