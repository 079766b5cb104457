"""Layered costmaps with Nav2 costmap_2d semantics (pure numpy).

Typical global costmap::

    params = CostmapParams()
    costmap = LayeredCostmap(params, [StaticLayer(params), ObstacleLayer(params), InflationLayer()])
    costmap.set_map(occupancy.data, occupancy.spec)
    costmap.update(robot_pose)
"""

from nav_stack.core.costmap.footprint import Footprint, footprint_cost, footprint_costs
from nav_stack.core.costmap.inflation_layer import InflationLayer, inflation_cost
from nav_stack.core.costmap.layer import Layer, Window
from nav_stack.core.costmap.layered import LayeredCostmap
from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.costmap.obstacle_layer import ObstacleLayer
from nav_stack.core.costmap.params import (
    CostmapParams,
    InflationLayerParams,
    ObstacleLayerParams,
    StaticLayerParams,
)
from nav_stack.core.costmap.static_layer import StaticLayer, costs_from_occupancy

__all__ = [
    "CostmapParams",
    "Footprint",
    "InflationLayer",
    "InflationLayerParams",
    "LaserScan",
    "Layer",
    "LayeredCostmap",
    "ObstacleLayer",
    "ObstacleLayerParams",
    "StaticLayer",
    "StaticLayerParams",
    "Window",
    "costs_from_occupancy",
    "footprint_cost",
    "footprint_costs",
    "inflation_cost",
]
