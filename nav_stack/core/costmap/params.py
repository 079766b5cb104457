"""Parameters of a costmap and its layers, one frozen dataclass each, with Nav2's names.

Why: the lifecycle node declares one ROS parameter per field (same names as nav2_costmap_2d, so a
Nav2 params file works) and builds these objects; the defaults here are the only copy. Defaults
are the Jazzy nav2_bringup ``nav2_params.yaml`` values where that file sets them (global costmap),
else the C++ code defaults; :meth:`CostmapParams.local_defaults` gives the yaml's local costmap.
Distances in metres, frequencies in Hz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

Point2 = tuple[float, float]


def _check_positive(owner: str, **values: float) -> None:
    for name, value in values.items():
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{owner}.{name} must be a positive number, got {value!r}")


def _check_non_negative(owner: str, **values: float) -> None:
    for name, value in values.items():
        if not (math.isfinite(value) and value >= 0.0):
            raise ValueError(f"{owner}.{name} must be a non-negative number, got {value!r}")


@dataclass(frozen=True)
class CostmapParams:
    """Costmap2DROS parameters (``global_costmap``/``local_costmap`` ``ros__parameters``).

    ``footprint`` is a polygon in the robot frame (m); when empty, a 16-gon of ``robot_radius``
    is used, as Nav2 does. ``width``/``height`` (m) only matter for a rolling window; a static
    costmap takes its size from the map.
    """

    global_frame: str = "map"
    robot_base_frame: str = "base_link"
    update_frequency: float = 1.0
    publish_frequency: float = 1.0
    transform_tolerance: float = 0.3
    resolution: float = 0.05
    width: float = 5.0
    height: float = 5.0
    origin_x: float = 0.0
    origin_y: float = 0.0
    rolling_window: bool = False
    track_unknown_space: bool = True
    lethal_cost_threshold: int = 100
    unknown_cost_value: int = 255
    trinary_costmap: bool = True
    robot_radius: float = 0.22
    footprint: tuple[Point2, ...] = ()
    footprint_padding: float = 0.01
    # True: the whole grid every publish cycle (the Jazzy yaml's value; Nav2's C++ default is false);
    # false: the whole grid once, then costmap_updates / costmap_raw_updates
    # (nav_stack.ros.costmap.costmap_publisher)
    always_send_full_costmap: bool = True

    def __post_init__(self) -> None:
        _check_positive("CostmapParams", resolution=self.resolution, width=self.width, height=self.height,
                        update_frequency=self.update_frequency, publish_frequency=self.publish_frequency)
        _check_non_negative("CostmapParams", transform_tolerance=self.transform_tolerance,
                            footprint_padding=self.footprint_padding)
        if not self.footprint:
            _check_positive("CostmapParams", robot_radius=self.robot_radius)
        elif len(self.footprint) < 3:
            raise ValueError(f"CostmapParams.footprint needs at least 3 points, got {self.footprint!r}")
        if not 0 <= self.lethal_cost_threshold <= 255:
            raise ValueError(
                f"CostmapParams.lethal_cost_threshold must be 0..255, got {self.lethal_cost_threshold}")

    @classmethod
    def local_defaults(cls) -> CostmapParams:
        """The Jazzy yaml's local costmap: odom frame, 3 m × 3 m rolling window, 5 Hz / 2 Hz."""
        return replace(cls(), global_frame="odom", rolling_window=True, width=3.0, height=3.0,
                       track_unknown_space=False, update_frequency=5.0, publish_frequency=2.0)


@dataclass(frozen=True)
class StaticLayerParams:
    """nav2_costmap_2d::StaticLayer (``static_layer``)."""

    # Accepted so a Nav2 file loads, never read (nav_stack.ros.common.params warns at startup).
    IGNORED: ClassVar[dict[str, str]] = {
        "subscribe_to_updates": "map_updates is not subscribed; a new /map replaces the whole map",
    }

    enabled: bool = True
    use_maximum: bool = False
    map_topic: str = "map"
    subscribe_to_updates: bool = False
    map_subscribe_transient_local: bool = True


@dataclass(frozen=True)
class ObstacleLayerParams:
    """nav2_costmap_2d::ObstacleLayer (``obstacle_layer``) with its single ``scan`` source.

    ``combination_method``: 0 overwrites the master with known cells, 1 takes the maximum.
    """

    enabled: bool = True
    footprint_clearing_enabled: bool = True
    combination_method: int = 1
    observation_sources: str = "scan"
    topic: str = "/scan"
    marking: bool = True
    clearing: bool = True
    obstacle_max_range: float = 2.5
    obstacle_min_range: float = 0.0
    raytrace_max_range: float = 3.0
    raytrace_min_range: float = 0.0
    inf_is_valid: bool = False

    def __post_init__(self) -> None:
        _check_non_negative("ObstacleLayerParams", obstacle_max_range=self.obstacle_max_range,
                            obstacle_min_range=self.obstacle_min_range,
                            raytrace_max_range=self.raytrace_max_range,
                            raytrace_min_range=self.raytrace_min_range)
        if self.combination_method not in (0, 1):
            raise ValueError(
                f"ObstacleLayerParams.combination_method must be 0 or 1, got {self.combination_method}")


@dataclass(frozen=True)
class InflationLayerParams:
    """nav2_costmap_2d::InflationLayer (``inflation_layer``)."""

    enabled: bool = True
    inflation_radius: float = 0.70
    cost_scaling_factor: float = 3.0
    inflate_unknown: bool = False

    def __post_init__(self) -> None:
        _check_non_negative("InflationLayerParams", inflation_radius=self.inflation_radius,
                            cost_scaling_factor=self.cost_scaling_factor)
