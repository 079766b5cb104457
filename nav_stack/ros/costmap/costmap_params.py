"""ROS parameters of a costmap node, laid out as Nav2's Costmap2DROS reads them.

Why a module: Nav2's layout does not map one dataclass to one prefix. ``footprint`` is a string
``"[[x, y], ...]"`` (a ROS parameter cannot be a list of lists); the obstacle layer keeps its
per-sensor knobs under ``<layer>.<source>.`` (``obstacle_layer.scan.raytrace_max_range``); layers are
listed in ``plugins`` and typed by ``<layer>.plugin``. This module declares those names with the
core dataclasses' defaults (through :func:`declare_dataclass`) and builds the core layers.
"""

from __future__ import annotations

import dataclasses

import yaml
from rclpy.node import Node

from nav_stack.core.costmap import (
    CostmapParams,
    InflationLayer,
    InflationLayerParams,
    Layer,
    ObstacleLayer,
    ObstacleLayerParams,
    StaticLayer,
    StaticLayerParams,
)
from nav_stack.ros.bringup.param_layout import build, declare_fields, param
from nav_stack.ros.common.params import declare_dataclass

#: ObstacleLayerParams fields Nav2 reads per observation source (``<layer>.<source>.<field>``).
SOURCE_FIELDS = ("topic", "marking", "clearing", "obstacle_max_range", "obstacle_min_range",
                 "raytrace_max_range", "raytrace_min_range", "inf_is_valid")
GLOBAL_PLUGINS = ("static_layer", "obstacle_layer", "inflation_layer")
LOCAL_PLUGINS = ("obstacle_layer", "inflation_layer")
_STATIC = "StaticLayer"
_OBSTACLE = ("ObstacleLayer", "VoxelLayer")  # a voxel layer is served by the 2D obstacle layer
_INFLATION = "InflationLayer"


def parse_footprint(text: str, node_name: str, param: str = "footprint") -> tuple[tuple[float, float], ...]:
    """Nav2's footprint string ``"[[x, y], [x, y], ...]"`` (m, robot frame); ``"[]"`` = use robot_radius."""
    try:
        points = yaml.safe_load(text) if text.strip() else []
        footprint = tuple((float(x), float(y)) for x, y in points or [])
    except (yaml.YAMLError, TypeError, ValueError) as error:
        raise ValueError(f"{node_name}: parameter {param} must look like '[[x, y], ...]', got {text!r}") \
            from error
    return footprint


def declare_costmap_params(node: Node, defaults: CostmapParams) -> CostmapParams:
    """CostmapParams from the node's parameters (Nav2 names; ``footprint`` as Nav2's string)."""
    names = [f.name for f in dataclasses.fields(CostmapParams) if f.name != "footprint"]
    values = declare_fields(node, CostmapParams, names, "", **dataclasses.asdict(defaults))
    text = param(node, "footprint", str([list(p) for p in defaults.footprint]))
    values["footprint"] = parse_footprint(str(text), node.get_name())
    return build(node, CostmapParams, values, "costmap")  # type: ignore[no-any-return]


def _obstacle_params(node: Node, name: str) -> ObstacleLayerParams:
    layer_fields = [f.name for f in dataclasses.fields(ObstacleLayerParams) if f.name not in SOURCE_FIELDS]
    values = declare_fields(node, ObstacleLayerParams, layer_fields, f"{name}.")
    sources = [s for s in str(values["observation_sources"]).split() if s]
    if len(sources) != 1:
        raise ValueError(f"{node.get_name()}: {name}.observation_sources must name exactly one laser "
                         f"source, got {values['observation_sources']!r}")
    values.update(declare_fields(node, ObstacleLayerParams, SOURCE_FIELDS, f"{name}.{sources[0]}."))
    return build(node, ObstacleLayerParams, values, name)  # type: ignore[no-any-return]


def build_layers(node: Node, params: CostmapParams) -> list[Layer]:
    """The layers named by the ``plugins`` parameter, in order, each typed by ``<name>.plugin``."""
    default = LOCAL_PLUGINS if params.rolling_window else GLOBAL_PLUGINS
    names = list(param(node, "plugins", list(default)) or [])
    layers: list[Layer] = []
    for name in names:
        kind_default = {"static_layer": _STATIC, "obstacle_layer": _OBSTACLE[0],
                        "voxel_layer": _OBSTACLE[1], "inflation_layer": _INFLATION}.get(name, "")
        plugin = str(param(node, f"{name}.plugin", f"nav2_costmap_2d::{kind_default}"))
        kind = plugin.replace("/", "::").split("::")[-1]
        if kind == _STATIC:
            layers.append(StaticLayer(params, declare_dataclass(node, StaticLayerParams, f"{name}."), name))
        elif kind in _OBSTACLE:
            layers.append(ObstacleLayer(params, _obstacle_params(node, name), name))
        elif kind == _INFLATION:
            layers.append(InflationLayer(declare_dataclass(node, InflationLayerParams, f"{name}."), name))
        else:
            raise ValueError(f"{node.get_name()}: {name}.plugin '{plugin}' is not a known layer "
                             f"(nav2_costmap_2d::StaticLayer, ObstacleLayer, VoxelLayer, InflationLayer)")
    return layers
