"""The critics' parameters and the cycle's scalars as the arrays critics_jit.score reads.

Why: compiled code takes arrays, not dataclasses. Each critic becomes a code (its place in
critics_jit.CRITIC_CODES, DISABLED when ``enabled`` is false) and a row of floats in the order of
FIELDS; the cycle's scalars go into ``ctx`` at critics_jit's C_* indices.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from nav_stack.core.control.mppi import critics_jit as cj
from nav_stack.core.control.mppi.params import MPPIParams
from nav_stack.core.control.mppi.path_critics import effective_path_angle_mode
from nav_stack.core.control.mppi.scene import Scene

F64 = npt.NDArray[np.float64]

#: the parameter row of each critic, in the order critics_jit reads it
FIELDS: dict[str, tuple[str, ...]] = {
    "ConstraintCritic": ("cost_weight", "cost_power"),
    "CostCritic": ("cost_weight", "cost_power", "critical_cost", "near_collision_cost", "consider_footprint",
                   "collision_cost", "near_goal_distance", "trajectory_point_step"),
    "ObstaclesCritic": ("cost_power", "consider_footprint", "critical_weight", "repulsion_weight",
                        "collision_cost", "collision_margin_distance", "near_goal_distance",
                        "inflation_radius", "cost_scaling_factor"),
    "GoalCritic": ("cost_weight", "cost_power", "threshold_to_consider"),
    "GoalAngleCritic": ("cost_weight", "cost_power", "threshold_to_consider"),
    "PathAlignCritic": ("cost_weight", "cost_power", "max_path_occupancy_ratio", "trajectory_point_step",
                        "threshold_to_consider", "offset_from_furthest", "use_path_orientations"),
    "PathFollowCritic": ("cost_weight", "cost_power", "offset_from_furthest", "threshold_to_consider"),
    "PathAngleCritic": ("cost_weight", "cost_power", "offset_from_furthest", "threshold_to_consider",
                        "max_angle_to_furthest", "mode"),
    "PreferForwardCritic": ("cost_weight", "cost_power", "threshold_to_consider"),
    "TwirlingCritic": ("cost_weight", "cost_power"),
}
WIDTH = max(len(f) for f in FIELDS.values())


def pack(critics: Sequence[tuple[str, Any]], params: MPPIParams) -> tuple[npt.NDArray[np.int64], F64]:
    """The critics as codes (DISABLED for a disabled one) and parameter rows, in list order."""
    codes = np.full(len(critics), cj.DISABLED, dtype=np.int64)
    table = np.zeros((len(critics), WIDTH))
    for k, (name, p) in enumerate(critics):
        if p.enabled:
            codes[k] = cj.CRITIC_CODES[name]
        row = [float(getattr(p, f)) for f in FIELDS[name]]
        if name == "PathAngleCritic":
            row[-1] = float(effective_path_angle_mode(p.mode, params))
        table[k, : len(row)] = row
    return codes, table


def context(scene: Scene, p: MPPIParams, min_turning_r: float) -> F64:
    """The cycle's scalars, at critics_jit's C_* indices."""
    ctx = np.zeros(cj.CTX_SIZE)
    ctx[cj.C_ROBOT_X], ctx[cj.C_ROBOT_Y], ctx[cj.C_ROBOT_YAW] = scene.robot
    ctx[cj.C_GOAL_X], ctx[cj.C_GOAL_Y], ctx[cj.C_GOAL_YAW] = scene.goal[:3]
    ctx[cj.C_DT], ctx[cj.C_VX_MAX] = p.model_dt, p.vx_max
    ctx[cj.C_VX_MIN], ctx[cj.C_VY_MAX] = p.vx_min, p.vy_max
    ctx[cj.C_MIN_TURNING_R], ctx[cj.C_GOAL_DIST_TOL] = min_turning_r, p.goal_dist_tol
    ctx[cj.C_CIRCUMSCRIBED] = scene.footprint.circumscribed_cost
    ctx[cj.C_INSCRIBED] = scene.footprint.inscribed_radius
    ctx[cj.C_MODEL] = int(p.model)
    return ctx
