"""Controller, goal-checker and progress-checker plugins of controller_server, built from Nav2 parameters.

Plugin ids come from ``controller_plugins``, ``goal_checker_plugins``, ``progress_checker_plugins``;
each id's type from ``<id>.plugin`` (Nav2 class names, ``::`` or Humble's ``/``), its knobs from
``<id>.<knob>``. DWB critic knobs use Nav2's spelling (``FollowPath.PathAlign.scale``). RPP's
inscribed radius comes from the local costmap, its goal distance from the goal checker and its
rate from ``controller_frequency``, as in Nav2, not from its own parameters. MPPI's knobs are
``<id>.<knob>``, its critics' ``<id>.<Critic>.<knob>`` (``FollowPath.CostCritic.cost_weight``), its
Ackermann radius ``<id>.AckermannConstraints.min_turning_r``, its visualisation's
``<id>.TrajectoryVisualizer.*``; the local costmap's inflation layer gives what its critics need to
know of the inflation, as in Nav2.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from rclpy.node import Node

from nav_stack.core.control import (
    MPPI_CRITIC_PARAMS,
    AckermannConstraints,
    ControllerPlugins,
    DWBController,
    DWBParams,
    Footprint,
    GoalCheckerParams,
    MPPIController,
    MPPIParams,
    ProgressCheckerParams,
    RegulatedPurePursuit,
    RPPParams,
    SimpleGoalChecker,
    SimpleProgressChecker,
    StoppedGoalChecker,
    TrajectoryVisualizerParams,
)
from nav_stack.core.control.mppi import kernels_jit as mppi_kernels
from nav_stack.core.control.rotation_shim import RotationShim, RotationShimParams
from nav_stack.core.control.server import LocalController
from nav_stack.core.costmap.inflation_layer import InflationLayer
from nav_stack.ros.bringup.param_layout import build, declare_fields, declare_renamed, param
from nav_stack.ros.bringup.plugin_catalog import CONTROLLERS, class_name
from nav_stack.ros.common.params import declare_dataclass, on_dataclass_update

DWB_CRITIC_NAMES = {
    "base_obstacle_scale": "BaseObstacle.scale",
    "base_obstacle_sum_scores": "BaseObstacle.sum_scores",
    "path_align_scale": "PathAlign.scale",
    "path_align_forward_point_distance": "PathAlign.forward_point_distance",
    "goal_align_scale": "GoalAlign.scale",
    "goal_align_forward_point_distance": "GoalAlign.forward_point_distance",
    "path_dist_scale": "PathDist.scale",
    "goal_dist_scale": "GoalDist.scale",
    "rotate_to_goal_scale": "RotateToGoal.scale",
    "rotate_to_goal_slowing_factor": "RotateToGoal.slowing_factor",
    "rotate_to_goal_lookahead_time": "RotateToGoal.lookahead_time",
    "oscillation_scale": "Oscillation.scale",
    "oscillation_reset_dist": "Oscillation.oscillation_reset_dist",
    "oscillation_reset_angle": "Oscillation.oscillation_reset_angle",
    "x_only_threshold": "Oscillation.x_only_threshold",
}
RPP_FROM_SERVER = ("inscribed_radius", "goal_dist_tol", "controller_frequency")
SHIM_FROM_SERVER = ("goal_dist_tol", "controller_frequency")
MPPI_FROM_SERVER = ("goal_dist_tol", "controller_frequency")
CONTROLLER_TYPES = list(CONTROLLERS)
PRIMARY_TYPES = ("DWBLocalPlanner", "RegulatedPurePursuitController", "MPPIController")
DEFAULT_TYPES = {
    "FollowPath": "dwb_core::DWBLocalPlanner",
    "DWB": "dwb_core::DWBLocalPlanner",
    "RPP": "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController",
    "RotationShim": "nav2_rotation_shim_controller::RotationShimController",
    "MPPI": "nav2_mppi_controller::MPPIController",
    "general_goal_checker": "nav2_controller::SimpleGoalChecker",
    "goal_checker": "nav2_controller::SimpleGoalChecker",
    "stopped_goal_checker": "nav2_controller::StoppedGoalChecker",
    "progress_checker": "nav2_controller::SimpleProgressChecker",
}


def _kind(node: Node, plugin_id: str) -> str:
    return class_name(str(param(node, f"{plugin_id}.plugin", DEFAULT_TYPES.get(plugin_id, ""))))


def _unknown(node: Node, plugin_id: str, kind: str, known: Sequence[str]) -> ValueError:
    return ValueError(f"{node.get_name()}: {plugin_id}.plugin '{kind}' is not one of {list(known)}")


def _dwb(node: Node, plugin_id: str, footprint: Footprint) -> DWBController:
    flat = [f.name for f in dataclasses.fields(DWBParams) if f.name not in DWB_CRITIC_NAMES]
    values = declare_fields(node, DWBParams, flat, f"{plugin_id}.")
    values.update(declare_renamed(node, DWBParams, f"{plugin_id}.", DWB_CRITIC_NAMES))
    return DWBController(build(node, DWBParams, values, plugin_id), footprint)


def _rpp(
    node: Node, plugin_id: str, footprint: Footprint, from_server: dict[str, float]
) -> RegulatedPurePursuit:
    own = [f.name for f in dataclasses.fields(RPPParams) if f.name not in RPP_FROM_SERVER]
    values = declare_fields(node, RPPParams, own, f"{plugin_id}.") | from_server
    return RegulatedPurePursuit(build(node, RPPParams, values, plugin_id), footprint)


def _inflation(node: Node, layer_name: str) -> tuple[float, float] | None:
    """(inflation_radius m, cost_scaling_factor) of the local costmap's inflation layer named
    ``layer_name`` ("" = the last one), None without one (Nav2's InflationLayer::getInflationLayer)."""
    costmap = getattr(getattr(node, "costmap_node", None), "costmap", None)
    layers = [layer for layer in getattr(costmap, "layers", ()) if isinstance(layer, InflationLayer)]
    if layer_name:
        layers = [layer for layer in layers if layer.name == layer_name]
    if not layers:
        return None
    return layers[-1].params.inflation_radius, layers[-1].params.cost_scaling_factor


def _mppi(node: Node, cid: str, footprint: Footprint, server: dict[str, Any]) -> MPPIController:
    """MPPI with its ``<cid>.*`` knobs, one parameter set per listed critic (``<cid>.<Critic>.*``)."""
    own = [f.name for f in dataclasses.fields(MPPIParams) if f.name not in MPPI_FROM_SERVER]
    values = declare_fields(node, MPPIParams, own, f"{cid}.") | {k: server[k] for k in MPPI_FROM_SERVER}
    params: MPPIParams = build(node, MPPIParams, values, cid)
    obstacle_critics = [name for name in params.critics if name in ("CostCritic", "ObstaclesCritic")]
    layer_name = ""
    if obstacle_critics:  # read first: the chosen layer gives the critics' defaults below
        critic_cls: Any = MPPI_CRITIC_PARAMS[obstacle_critics[0]]
        layer_name = str(param(node, f"{cid}.{obstacle_critics[0]}.inflation_layer_name",
                               critic_cls.inflation_layer_name))
    inflation = _inflation(node, layer_name)
    critics: dict[str, Any] = {}
    for name in params.critics:
        defaults = {}
        if name == "ObstaclesCritic" and inflation is not None:  # Jazzy reads these from the layer
            defaults = {"inflation_radius": inflation[0], "cost_scaling_factor": inflation[1]}
        critics[name] = declare_dataclass(node, MPPI_CRITIC_PARAMS[name], f"{cid}.{name}.", **defaults)
    mppi_kernels.warm_up()  # load the compiled kernels now, not in the first control cycle
    return MPPIController(
        params, critics, footprint,
        ackermann=declare_dataclass(node, AckermannConstraints, f"{cid}.AckermannConstraints."),
        visualizer=declare_dataclass(node, TrajectoryVisualizerParams, f"{cid}.TrajectoryVisualizer."),
        inscribed_radius=server["inscribed_radius"], inflation=inflation)


def _controller(
    node: Node, cid: str, kind: str, footprint: Footprint, server: dict[str, Any]
) -> LocalController:
    """The controller of plugin type ``kind`` with its ``<cid>.*`` parameters; a RotationShimController
    wraps the ``<cid>.primary_controller`` type, whose parameters share the prefix (Nav2's layout)."""
    if kind == "DWBLocalPlanner":
        return _dwb(node, cid, footprint)
    if kind == "RegulatedPurePursuitController":
        return _rpp(node, cid, footprint, {k: server[k] for k in RPP_FROM_SERVER})
    if kind == "MPPIController":
        return _mppi(node, cid, footprint, server)
    if kind == "RotationShimController":
        primary_type = str(param(node, f"{cid}.primary_controller", ""))
        primary_kind = class_name(primary_type)
        if primary_kind not in PRIMARY_TYPES:
            raise ValueError(f"{node.get_name()}: {cid}.primary_controller '{primary_type}' is not "
                             "dwb_core::DWBLocalPlanner, nav2_regulated_pure_pursuit_controller::"
                             "RegulatedPurePursuitController or nav2_mppi_controller::MPPIController")
        primary = _controller(node, cid, primary_kind, footprint, server)
        own = [f.name for f in dataclasses.fields(RotationShimParams) if f.name not in SHIM_FROM_SERVER]
        values = declare_fields(node, RotationShimParams, own, f"{cid}.")
        values |= {k: server[k] for k in SHIM_FROM_SERVER}
        return RotationShim(primary, build(node, RotationShimParams, values, cid), footprint)
    raise _unknown(node, cid, kind, CONTROLLER_TYPES)


def build_plugins(
    node: Node,
    controller_ids: Sequence[str],
    goal_checker_ids: Sequence[str],
    progress_checker_ids: Sequence[str],
    footprint: Footprint,
    inscribed_radius: float,
    controller_frequency: float,
) -> ControllerPlugins:
    """Every configured plugin; ValueError naming the id for an unknown ``plugin`` type."""
    goal_checkers: dict[str, SimpleGoalChecker] = {}
    for gid in goal_checker_ids:
        kind = _kind(node, gid)
        checker_cls = {"SimpleGoalChecker": SimpleGoalChecker,
                       "StoppedGoalChecker": StoppedGoalChecker}.get(kind)
        if checker_cls is None:
            raise _unknown(node, gid, kind, ["SimpleGoalChecker", "StoppedGoalChecker"])
        goal_checkers[gid] = checker_cls(declare_dataclass(node, GoalCheckerParams, f"{gid}."))
    progress: dict[str, SimpleProgressChecker] = {}
    for pid in progress_checker_ids:
        kind = _kind(node, pid)
        if kind != "SimpleProgressChecker":
            raise _unknown(node, pid, kind, ["SimpleProgressChecker"])
        progress[pid] = SimpleProgressChecker(declare_dataclass(node, ProgressCheckerParams, f"{pid}."))
    xy_tolerance = min((c.params.xy_goal_tolerance for c in goal_checkers.values()), default=0.25)
    server = {"inscribed_radius": inscribed_radius, "goal_dist_tol": xy_tolerance,
              "controller_frequency": controller_frequency}
    kinds = {cid: _kind(node, cid) for cid in controller_ids}
    controllers = {cid: _controller(node, cid, kind, footprint, server) for cid, kind in kinds.items()}
    node.get_logger().info("controllers: " + ", ".join(f"{cid} ({kind})" for cid, kind in kinds.items()))
    return ControllerPlugins(controllers, goal_checkers, progress)


def take_param_updates(node: Node, controllers: Mapping[str, LocalController]) -> list[Any]:
    """Let ``ros2 param set /controller_server FollowPath.desired_linear_vel 0.15`` (or a DWB knob,
    ``DWB.max_vel_x``) change a running controller from its next cycle, as Nav2's controllers do.
    Returns the parameter callbacks, to remove at cleanup."""
    callbacks = []
    for cid, outer in controllers.items():
        layers = [outer, outer.primary] if isinstance(outer, RotationShim) else [outer]
        for controller in layers:
            renames = DWB_CRITIC_NAMES if isinstance(controller, DWBController) else None
            callbacks.append(on_dataclass_update(node, type(controller.params), f"{cid}.",
                                                 _params_of(controller),
                                                 _replace_params(node, cid, controller), renames))
            if isinstance(controller, MPPIController):
                callbacks.extend(_mppi_critic_updates(node, cid, controller))
    return callbacks


def _mppi_critic_updates(node: Node, cid: str, controller: MPPIController) -> list[Any]:
    """``ros2 param set /controller_server FollowPath.CostCritic.cost_weight 5.0``: the critic's new
    parameters from the next cycle (the optimizer starts over, as Nav2's does)."""
    callbacks = []
    for name, current in controller.critic_params.items():
        def replace(params: Any, name: str = name) -> None:
            controller.set_critic_params(name, params)
            node.get_logger().info(f"{cid}.{name}: parameters updated")

        def now(name: str = name) -> Any:
            return controller.critic_params[name]

        callbacks.append(on_dataclass_update(node, type(current), f"{cid}.{name}.", now, replace))
    return callbacks


def _params_of(controller: Any) -> Callable[[], Any]:
    return lambda: controller.params


def _replace_params(node: Node, cid: str, controller: Any) -> Callable[[Any], None]:
    def replace(params: Any) -> None:
        controller.params = params
        node.get_logger().info(f"{cid}: parameters updated")

    return replace
