"""The node processes of nav-bringup: ``nav-bringup component <name>`` runs one of them.

A component is the set of Nav2-style nodes one process hosts on one executor, as Nav2's
``use_composition``: ``all`` (localization and navigation, the default), or ``localization`` and
``navigation`` apart (``nav-bringup --isolated``, and ``navigation`` next to SLAM). Which servers it
runs, and how their velocity commands chain, comes from the parameter files through
nav_stack/ros/bringup/bringup_plan.py, as nav2_bringup's launch files decide it. The process takes part in
lockstep under its role (``nav2`` for ``all``), prints COMPONENT_READY once its lifecycle managers
are active (the launcher's readiness line), says every WAIT_REPORT_S what it still waits for, and
ends with exit code 1 when a manager aborts its bringup.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any

from nav_stack.ros.bringup.bringup_plan import BOND_TIMEOUT, BringupPlan, ManagerPlan, plan_bringup
from nav_stack.ros.bringup.namespaced_params import namespace_remaps, namespaced_files, robot_namespace

COMPONENT_READY = "bringup: component {name} is active"
#: Nodes that publish velocity commands, each with Nav2's ``enable_stamped_cmd_vel`` (the chain's filters
#: read and write the same type, so all of them switch together).
STAMPED_PRODUCERS = ("controller_server", "behavior_server", "velocity_smoother", "collision_monitor",
                     "docking_server")
COMPONENTS = ("localization", "navigation", "all")
WAIT_REPORT_S = 5.0  # s (wall) between two "still waiting for" lines


def _server_builders(map_yaml: str | None, namespace: str = "") -> dict[str, Callable[[], list[Any]]]:
    """Node name → a function building that server (and the nodes it owns, e.g. its costmap).

    With a ``namespace`` (``/robot1``) every node is built in it, and each costmap in
    ``<namespace>/<costmap>`` with the namespace as its parent (the topics it names relatively,
    ``map`` and ``scan``, then resolve there, as Nav2's joinWithParentNamespace does).
    """
    from rclpy.parameter import Parameter

    from nav_stack.ros.behaviors import behavior_server
    from nav_stack.ros.collision import collision_monitor
    from nav_stack.ros.control import controller_server, velocity_smoother
    from nav_stack.ros.costmap.costmap_ros import CostmapROS
    from nav_stack.ros.docking import docking_server
    from nav_stack.ros.localization import amcl_node, map_server
    from nav_stack.ros.navigator import bt_navigator, waypoint_follower
    from nav_stack.ros.planning import planner_server, smoother_server

    overrides = [Parameter("yaml_filename", value=str(map_yaml))] if map_yaml else []
    where: dict[str, Any] = {"namespace": namespace} if namespace else {}

    def owning(costmap: str) -> dict[str, Any]:
        if not namespace:
            return {}
        return {**where, "costmap_node": CostmapROS(costmap, namespace=f"{namespace}/{costmap}",
                                                    parent_namespace=namespace)}

    return {
        "map_server": lambda: [map_server.MapServer(parameter_overrides=overrides, **where)],
        "amcl": lambda: [amcl_node.AmclNode(**where)],
        "controller_server": lambda: controller_server.build_nodes(**owning("local_costmap")),
        "smoother_server": lambda: smoother_server.build_nodes(**where),
        "planner_server": lambda: planner_server.build_nodes(**owning("global_costmap")),
        "behavior_server": lambda: behavior_server.build_nodes(**where),
        "velocity_smoother": lambda: velocity_smoother.build_nodes(**where),
        "collision_monitor": lambda: collision_monitor.build_nodes(**where),
        "bt_navigator": lambda: bt_navigator.build_nodes(**where),
        "waypoint_follower": lambda: waypoint_follower.build_nodes(**where),
        "docking_server": lambda: docking_server.build_nodes(**where),
    }


def _manager_nodes(manager: ManagerPlan, builders: dict[str, Callable[[], list[Any]]],
                   namespace: str = "") -> list[Any]:
    from nav_stack.ros.lifecycle.lifecycle_manager import LifecycleManager

    nodes: list[Any] = []
    for name in manager.node_names:
        nodes.extend(builders[name]())
    defaults = {"node_names": manager.node_names, "autostart": manager.autostart,
                "bond_timeout": BOND_TIMEOUT}
    nodes.append(LifecycleManager(manager.name, defaults=defaults,
                                  **({"namespace": namespace} if namespace else {})))
    return nodes


def waiting_for(managers: Sequence[Any], costmaps: Sequence[Any], clock_heard: bool,
                map_needed: bool) -> list[str]:
    """What a component that is not ready yet still waits for, one phrase per item."""
    items = []
    if not clock_heard:
        items.append("/clock (no message yet: is the simulator running?)")
    items += [f"{m.get_name()}: {m.step}" for m in managers if not m.system_active]
    if map_needed:
        items += [f"{c.get_name()}: the map on {c.resolve_topic_name('map')}" for c in costmaps
                  if not c.has_map]
    return items


def stamped_overlay(node_names: Sequence[str], directory: str | None = None) -> str:
    """A parameter file, written to a temporary file, that sets ``enable_stamped_cmd_vel: true`` for the
    velocity command producers among ``node_names``; its path. Only running nodes get a section: a
    section of its own makes an optional server (the velocity smoother) look configured."""
    import tempfile

    import yaml

    sections = {node: {"ros__parameters": {"enable_stamped_cmd_vel": True}}
                for node in node_names if node in STAMPED_PRODUCERS}
    with tempfile.NamedTemporaryFile("w", prefix="nav_bringup_stamped_", suffix=".yaml", dir=directory,
                                     delete=False) as handle:
        yaml.safe_dump(sections, handle)
    return handle.name


def run_component(name: str, params: Sequence[str], map_yaml: str | None, executor: str | None = None,
                  map_from_slam: bool = False, stamped_cmd_vel: bool = False, namespace: str = "") -> int:
    """Run the nodes of component ``name`` in this process; print COMPONENT_READY once its managers
    are active. The process is a lockstep participant named after the component, and holds the
    simulator until then and until its costmaps have their map (the stack's bringup takes the same
    sim time however slow the machine). With ``map_from_slam`` the map only comes once the simulator
    runs (SLAM builds it from scans), so the process does not wait for it. With ``stamped_cmd_vel``
    every velocity command producer it runs publishes TwistStamped, over what the files say (the launch runs
    a stamped simulator in lockstep: nav_stack/ros/bringup/nav_bringup.py). With a ``namespace`` (a fleet's
    robot, ``robot1``) every node runs under ``/robot1``, the parameter files are rewritten for it and its
    global topics remapped into it (nav_stack/ros/bringup/namespaced_params.py), and the lockstep role is
    ``robot1/<role>``."""
    from rclpy.clock import Clock, ClockType

    from nav_stack.ros.costmap.costmap_ros import CostmapROS
    from nav_stack.ros.lifecycle.lifecycle_manager import LifecycleManager
    from ros_tools.runtime.lockstep import clock_heard
    from ros_tools.runtime.runner import run_nodes

    plan: BringupPlan = plan_bringup(params, slam=map_from_slam)
    ns = robot_namespace(namespace) if namespace else ""
    managers: list[Any] = []
    costmaps: list[Any] = []

    def build() -> list[Any]:
        builders = _server_builders(map_yaml, ns)
        nodes: list[Any] = []
        if name in ("localization", "all") and plan.localization.node_names:
            nodes += _manager_nodes(plan.localization, builders, ns)
        if name in ("navigation", "all"):
            nodes += _manager_nodes(plan.navigation, builders, ns)
        managers.extend(node for node in nodes if isinstance(node, LifecycleManager))
        costmaps.extend(node for node in nodes if isinstance(node, CostmapROS))
        for note in plan.notes:
            managers[0].get_logger().info(note)
        return nodes

    def active() -> bool:
        return all(manager.system_active for manager in managers)

    def ready() -> bool:
        return active() and (map_from_slam or all(costmap.has_map for costmap in costmaps))

    failed: list[str] = []

    def announce_when_ready(_executor: Any, nodes: Any) -> None:
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        started = steady.now().nanoseconds
        last_report = [started]

        def announce() -> None:
            now = steady.now().nanoseconds
            if active():
                print(COMPONENT_READY.format(name=name), flush=True)
                managers[0].destroy_timer(timer)
            elif any(manager.bringup_failed for manager in managers):
                # Nav2's manager stays up after an aborted bringup and the launch would wait out its
                # readiness timeout; ending the process ends the launch at once, with the cause above.
                failed.extend(manager.get_name() for manager in managers if manager.bringup_failed)
                print(f"bringup: component {name} failed: {', '.join(failed)} aborted the bringup "
                      "(the node's error is above)", flush=True)
                managers[0].destroy_timer(timer)
                managers[0].context.try_shutdown()
            elif now - last_report[0] >= WAIT_REPORT_S * 1e9:
                last_report[0] = now
                heard = clock_heard()
                if heard is None:  # not in lockstep: a running simulator has moved the clock
                    heard = managers[0].get_clock().now().nanoseconds > 0
                items = waiting_for(managers, costmaps, heard, not map_from_slam)
                print(f"bringup: component {name} is waiting for "
                      f"{'; '.join(items) or 'its nodes'} ({(now - started) * 1e-9:.0f} s)", flush=True)

        timer = managers[0].create_timer(0.2, announce, clock=steady)

    files = [str(f) for f in params]
    temporary: list[str] = []
    if stamped_cmd_vel and name in ("navigation", "all"):
        temporary.append(stamped_overlay(plan.navigation.node_names))
        files.append(temporary[-1])  # the last file wins over the user's
    remaps = plan.ros_args()
    if ns:
        files = namespaced_files(files, ns)
        temporary += files
        remaps += [arg for rule in namespace_remaps(ns) for arg in ("-r", rule)]
    rclpy_args = ["nav_bringup", "--ros-args", *[arg for f in files for arg in ("--params-file", f)],
                  "-p", "use_sim_time:=true", *remaps]
    try:
        code = run_nodes(build, role=component_role(name, namespace), rclpy_args=rclpy_args,
                         executor=executor, ready=ready, on_start=announce_when_ready)
    finally:
        for path in temporary:
            os.unlink(path)
    return 1 if failed else code


def component_role(name: str, namespace: str = "") -> str:
    """The lockstep role (and launch name) of a component process: ``all`` runs as ``nav2``; a fleet
    robot's process as ``<robot>/<role>`` (``robot1/nav2``)."""
    role = "nav2" if name == "all" else name
    return f"{namespace.strip('/')}/{role}" if namespace.strip("/") else role
