"""The MPPI critics' parameters, one frozen dataclass per critic, under ``<id>.<Critic>.``.

Names and defaults are Nav2 Jazzy's (``FollowPath.CostCritic.cost_weight``); where Jazzy's
nav2_params.yaml sets a value, that is the default here and the code default is named in a comment
(see params.py for why). Every critic has ``enabled``, ``cost_power`` and, except the
ObstaclesCritic, ``cost_weight``: a critic adds (weight · term)^power to each trajectory's cost.
The formulas are in critics.py.
"""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from typing import Any, ClassVar


def _check(owner: str, positive_ints: tuple[str, ...] = (), non_negative: tuple[str, ...] = (),
           values: dict[str, Any] | None = None) -> None:
    values = values or {}
    for name in positive_ints:
        if values[name] < 1:
            raise ValueError(f"{owner}.{name} must be >= 1, got {values[name]}")
    for name in non_negative:
        if not values[name] >= 0:
            raise ValueError(f"{owner}.{name} must be >= 0, got {values[name]}")


class _Checked:
    """cost_power >= 1 and the listed fields >= 1 / >= 0, with a message naming the critic."""

    _POSITIVE: ClassVar[tuple[str, ...]] = ("cost_power",)
    _NON_NEGATIVE: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        values = dataclasses.asdict(self)  # type: ignore[call-overload]
        _check(type(self).__name__, self._POSITIVE, self._NON_NEGATIVE, values)


@dataclass(frozen=True)
class ConstraintCriticParams(_Checked):
    """Penalises time spent beyond the velocity limits (and, for Ackermann, inside min_turning_r)."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 4.0


@dataclass(frozen=True)
class CostCriticParams(_Checked):
    """Keeps trajectories off costly and lethal cells of the local costmap."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 3.81
    critical_cost: float = 300.0
    near_collision_cost: int = 253
    consider_footprint: bool = False
    collision_cost: float = 1000000.0
    near_goal_distance: float = 1.0  # m (code default 0.5)
    trajectory_point_step: int = 2
    inflation_layer_name: str = ""  # which inflation layer gives the circumscribed cost ("" = the last)

    _POSITIVE = ("cost_power", "trajectory_point_step")
    _NON_NEGATIVE = ("near_goal_distance",)


@dataclass(frozen=True)
class ObstaclesCriticParams(_Checked):
    """The older obstacle critic: distances recovered from inflated costs.

    ``inflation_radius`` and ``cost_scaling_factor`` are Humble's parameters; Jazzy reads them from
    the costmap's inflation layer, which is what the controller server's plugin loader passes as
    their defaults (an explicit value still wins).
    """

    enabled: bool = True
    cost_power: int = 1
    consider_footprint: bool = False
    critical_weight: float = 20.0
    repulsion_weight: float = 1.5
    collision_cost: float = 100000.0
    collision_margin_distance: float = 0.10  # m
    near_goal_distance: float = 0.5  # m
    inflation_radius: float = 0.55  # m
    cost_scaling_factor: float = 10.0
    inflation_layer_name: str = ""

    _NON_NEGATIVE = ("collision_margin_distance", "near_goal_distance", "inflation_radius",
                     "cost_scaling_factor")


@dataclass(frozen=True)
class GoalCriticParams(_Checked):
    """Pulls trajectory points toward the goal once it is within threshold_to_consider."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 5.0
    threshold_to_consider: float = 1.4  # m

    _NON_NEGATIVE = ("threshold_to_consider",)


@dataclass(frozen=True)
class GoalAngleCriticParams(_Checked):
    """Turns trajectories onto the goal heading once the goal is within threshold_to_consider."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 3.0
    threshold_to_consider: float = 0.5  # m

    _NON_NEGATIVE = ("threshold_to_consider",)


@dataclass(frozen=True)
class PathAlignCriticParams(_Checked):
    """Keeps trajectories on the path, point by point at equal distances along both."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 14.0  # code default 10.0
    max_path_occupancy_ratio: float = 0.05  # code default 0.07
    trajectory_point_step: int = 4
    threshold_to_consider: float = 0.5  # m
    offset_from_furthest: int = 20
    use_path_orientations: bool = False

    _POSITIVE = ("cost_power", "trajectory_point_step")
    _NON_NEGATIVE = ("max_path_occupancy_ratio", "threshold_to_consider", "offset_from_furthest")


@dataclass(frozen=True)
class PathFollowCriticParams(_Checked):
    """Drives trajectory ends toward a path point ``offset_from_furthest`` beyond the furthest reached."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 5.0
    offset_from_furthest: int = 5  # code default 6
    threshold_to_consider: float = 1.4  # m

    _NON_NEGATIVE = ("offset_from_furthest", "threshold_to_consider")


class PathAngleMode(enum.IntEnum):
    """PathAngleCritic ``mode``."""

    FORWARD_PREFERENCE = 0
    NO_DIRECTIONAL_PREFERENCE = 1
    CONSIDER_FEASIBLE_PATH_ORIENTATIONS = 2


@dataclass(frozen=True)
class PathAngleCriticParams(_Checked):
    """Turns the robot toward the path when it points far away from it."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 2.0  # code default 2.2
    offset_from_furthest: int = 4
    threshold_to_consider: float = 0.5  # m
    max_angle_to_furthest: float = 1.0  # rad (code default 0.785398)
    mode: int = 0  # PathAngleMode

    _NON_NEGATIVE = ("offset_from_furthest", "threshold_to_consider", "max_angle_to_furthest")

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.mode not in tuple(PathAngleMode):
            raise ValueError(f"PathAngleCriticParams.mode must be 0, 1 or 2, got {self.mode}")


@dataclass(frozen=True)
class PreferForwardCriticParams(_Checked):
    """Penalises reversing, away from the goal."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 5.0
    threshold_to_consider: float = 0.5  # m

    _NON_NEGATIVE = ("threshold_to_consider",)


@dataclass(frozen=True)
class TwirlingCriticParams(_Checked):
    """Penalises yaw rate (meant for holonomic robots), away from the goal."""

    enabled: bool = True
    cost_power: int = 1
    cost_weight: float = 10.0


#: critic name (as in ``critics``) → its parameter dataclass
CRITIC_PARAMS: dict[str, type] = {
    "ConstraintCritic": ConstraintCriticParams,
    "CostCritic": CostCriticParams,
    "ObstaclesCritic": ObstaclesCriticParams,
    "GoalCritic": GoalCriticParams,
    "GoalAngleCritic": GoalAngleCriticParams,
    "PathAlignCritic": PathAlignCriticParams,
    "PathFollowCritic": PathFollowCriticParams,
    "PathAngleCritic": PathAngleCriticParams,
    "PreferForwardCritic": PreferForwardCriticParams,
    "TwirlingCritic": TwirlingCriticParams,
}
