"""The node processes of nav-bringup: ``nav-bringup component <name>`` runs one of them.

A component is the set of Nav2-style nodes one process hosts on one executor, as Nav2's
``use_composition``: ``all`` (localization and navigation, the default), or ``localization`` and
``navigation`` apart (``nav-bringup --isolated``, and ``navigation`` next to SLAM). The process takes
part in lockstep under its role (``nav2`` for ``all``), prints COMPONENT_READY once its lifecycle
managers are active (the launcher's readiness line), and ends with exit code 1 when a manager
aborts its bringup.
"""

from __future__ import annotations

from typing import Any

COMPONENT_READY = "bringup: component {name} is active"
COMPONENTS = ("localization", "navigation", "all")


def _localization_nodes(kwargs: dict[str, Any], map_yaml: str | None) -> list[Any]:
    from rclpy.parameter import Parameter

    from nav_stack.ros.amcl_node import AmclNode
    from nav_stack.ros.lifecycle_manager import LifecycleManager
    from nav_stack.ros.map_server import MapServer

    overrides = [Parameter("yaml_filename", value=str(map_yaml))] if map_yaml else []
    return [MapServer(parameter_overrides=overrides, **kwargs), AmclNode(**kwargs),
            LifecycleManager("lifecycle_manager_localization", **kwargs)]


def _navigation_nodes(kwargs: dict[str, Any]) -> list[Any]:
    from nav_stack.ros import (
        behavior_server,
        bt_navigator,
        controller_server,
        planner_server,
        waypoint_follower,
    )
    from nav_stack.ros.lifecycle_manager import LifecycleManager

    nodes: list[Any] = []
    for module in (planner_server, controller_server, behavior_server, bt_navigator, waypoint_follower):
        nodes.extend(module.build_nodes(**kwargs))
    nodes.append(LifecycleManager("lifecycle_manager_navigation", **kwargs))
    return nodes


def run_component(name: str, params: str, map_yaml: str | None, executor: str | None = None,
                  map_from_slam: bool = False) -> int:
    """Run the nodes of component ``name`` in this process; print COMPONENT_READY once its managers
    are active. The process is a lockstep participant named after the component, and holds the
    simulator until then and until its costmaps have their map (the stack's bringup takes the same
    sim time however slow the machine). With ``map_from_slam`` the map only comes once the simulator
    runs (SLAM builds it from scans), so the process does not wait for it."""
    from rclpy.clock import Clock, ClockType

    import nav_stack.ros  # noqa: F401 - LOCALHOST discovery default
    from nav_stack.ros.costmap_ros import CostmapROS
    from nav_stack.ros.lifecycle_manager import LifecycleManager
    from ros_tools.runtime.runner import run_nodes

    managers: list[Any] = []
    costmaps: list[Any] = []

    def build() -> list[Any]:
        nodes: list[Any] = []
        if name in ("localization", "all"):
            nodes += _localization_nodes({}, map_yaml)
        if name in ("navigation", "all"):
            nodes += _navigation_nodes({})
        managers.extend(node for node in nodes if isinstance(node, LifecycleManager))
        costmaps.extend(node for node in nodes if isinstance(node, CostmapROS))
        return nodes

    def active() -> bool:
        return all(manager.system_active for manager in managers)

    def ready() -> bool:
        return active() and (map_from_slam or all(costmap.has_map for costmap in costmaps))

    failed: list[str] = []

    def announce_when_active(_executor: Any, nodes: Any) -> None:
        def announce() -> None:
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

        timer = managers[0].create_timer(0.2, announce, clock=Clock(clock_type=ClockType.STEADY_TIME))

    rclpy_args = ["nav_bringup", "--ros-args", "--params-file", params, "-p", "use_sim_time:=true"]
    code = run_nodes(build, role=component_role(name), rclpy_args=rclpy_args, executor=executor,
                     ready=ready, on_start=announce_when_active)
    return 1 if failed else code


def component_role(name: str) -> str:
    """The lockstep role (and launch name) of a component process: ``all`` runs as ``nav2``."""
    return "nav2" if name == "all" else name
