"""Local controllers (DWB, Regulated Pure Pursuit), path handling and goal/progress checkers."""

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
from nav_stack.core.control.path_handler import PathHandler, PathHandlerParams
from nav_stack.core.control.rpp import RegulatedPurePursuit
from nav_stack.core.control.rpp_params import RPPParams
from nav_stack.core.control.server import ControllerPlugins, InvalidController, LocalController

__all__ = [
    "FINAL_TURN_PROGRESS",
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
    "Twist2D",
]
