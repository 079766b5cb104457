"""Local controllers (DWB, Regulated Pure Pursuit, MPPI), path handling and goal/progress checkers."""

from nav_stack.core.control.base import (
    CircleFootprint,
    ControllerError,
    ControllerErrorCode,
    CostGrid,
    Footprint,
    InvalidPath,
    NoValidControl,
    PolygonFootprint,
    Twist2D,
)
from nav_stack.core.control.checkers import (
    FINAL_TURN_PROGRESS,
    GoalCheckerParams,
    ProgressCheckerParams,
    SimpleGoalChecker,
    SimpleProgressChecker,
    StoppedGoalChecker,
)
from nav_stack.core.control.dwb import DWBController, DWBParams
from nav_stack.core.control.mppi import (
    CRITIC_PARAMS as MPPI_CRITIC_PARAMS,
)
from nav_stack.core.control.mppi import (
    AckermannConstraints,
    MPPIController,
    MPPIParams,
    TrajectoryVisualizerParams,
    trajectory_markers,
)
from nav_stack.core.control.path_handler import PathHandler, PathHandlerParams
from nav_stack.core.control.rpp import RegulatedPurePursuit
from nav_stack.core.control.rpp_params import RPPParams
from nav_stack.core.control.server import ControllerPlugins, InvalidController, LocalController

__all__ = [
    "FINAL_TURN_PROGRESS",
    "MPPI_CRITIC_PARAMS",
    "AckermannConstraints",
    "CircleFootprint",
    "ControllerError",
    "ControllerErrorCode",
    "ControllerPlugins",
    "CostGrid",
    "DWBController",
    "DWBParams",
    "Footprint",
    "GoalCheckerParams",
    "InvalidController",
    "InvalidPath",
    "LocalController",
    "MPPIController",
    "MPPIParams",
    "NoValidControl",
    "PathHandler",
    "PathHandlerParams",
    "PolygonFootprint",
    "ProgressCheckerParams",
    "RPPParams",
    "RegulatedPurePursuit",
    "SimpleGoalChecker",
    "SimpleProgressChecker",
    "StoppedGoalChecker",
    "TrajectoryVisualizerParams",
    "Twist2D",
    "trajectory_markers",
]
