"""Nav2 Jazzy's MPPI controller (nav2_mppi_controller): parameters, critics, optimizer, compiled kernels.

Layout: params.py / critic_params.py (the knobs), scene.py (one cycle's inputs), reference.py +
critics.py + path_critics.py (one iteration in numpy, the definition), kernels_jit.py + critics_jit.py
(the same, compiled; packing.py turns the knobs into their arrays), noise.py (sampling noise),
optimizer.py (the state kept between cycles, smoothing, limits, fallback; sequence_jit.py compiles
its smoothing, clamps and optimal trajectory), local_path.py (what the critics see of the path),
controller.py (the LocalController), visualization.py (what the TrajectoryVisualizer draws).
"""

from nav_stack.core.control.mppi.controller import MPPIController
from nav_stack.core.control.mppi.critic_params import (
    CRITIC_PARAMS,
    ConstraintCriticParams,
    CostCriticParams,
    GoalAngleCriticParams,
    GoalCriticParams,
    ObstaclesCriticParams,
    PathAlignCriticParams,
    PathAngleCriticParams,
    PathAngleMode,
    PathFollowCriticParams,
    PreferForwardCriticParams,
    TwirlingCriticParams,
)
from nav_stack.core.control.mppi.params import (
    JAZZY_CRITICS,
    AckermannConstraints,
    MotionModel,
    MPPIParams,
    TrajectoryVisualizerParams,
)
from nav_stack.core.control.mppi.visualization import MarkerSet, trajectory_markers

__all__ = [
    "CRITIC_PARAMS",
    "JAZZY_CRITICS",
    "AckermannConstraints",
    "ConstraintCriticParams",
    "CostCriticParams",
    "GoalAngleCriticParams",
    "GoalCriticParams",
    "MPPIController",
    "MPPIParams",
    "MarkerSet",
    "MotionModel",
    "ObstaclesCriticParams",
    "PathAlignCriticParams",
    "PathAngleCriticParams",
    "PathAngleMode",
    "PathFollowCriticParams",
    "PreferForwardCriticParams",
    "TrajectoryVisualizerParams",
    "TwirlingCriticParams",
    "trajectory_markers",
]
