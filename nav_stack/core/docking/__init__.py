"""Docking (Nav2 Jazzy's opennav_docking) without ROS: the dock database, the SimpleChargingDock plugin,
the graceful controller and the DockRobot/UndockRobot sequences.

Modules: ``errors`` (result codes, feedback states, failures), ``spatial`` (3-D poses for detections),
``database`` (dock instances and plugins), ``simple_charging_dock`` (the dock plugin), ``graceful``
(the smooth control law), ``controller`` (law + collision look-ahead), ``params`` (server knobs),
``world`` (what the sequences need and return), ``sequence`` (DockRobot) and ``undocking`` (UndockRobot).
"""

from nav_stack.core.docking.controller import DockingController, DockingControllerParams, Obstacles
from nav_stack.core.docking.database import (
    Dock,
    DockDatabase,
    DockDatabaseError,
    dock_from_fields,
    docks_from_yaml,
    load_dock_file,
)
from nav_stack.core.docking.errors import DockErrorCode, DockingError, DockingState, FrameUnavailable
from nav_stack.core.docking.graceful import SmoothControlLawParams, velocity_command
from nav_stack.core.docking.params import DockingServerParams
from nav_stack.core.docking.sequence import DockingSequence, DockRequest
from nav_stack.core.docking.simple_charging_dock import (
    SIMPLE_CHARGING_DOCK,
    SIMPLE_NON_CHARGING_DOCK,
    Detection,
    SimpleChargingDock,
    SimpleChargingDockParams,
    dock_pose_from_tag,
)
from nav_stack.core.docking.spatial import Pose3D
from nav_stack.core.docking.undocking import UndockingSequence, UndockRequest
from nav_stack.core.docking.world import DockingOutcome, DockingResult, DockingStep, DockingWorld, StagingGoal

__all__ = [
    "SIMPLE_CHARGING_DOCK",
    "SIMPLE_NON_CHARGING_DOCK",
    "Detection",
    "Dock",
    "DockDatabase",
    "DockDatabaseError",
    "DockErrorCode",
    "DockRequest",
    "DockingController",
    "DockingControllerParams",
    "DockingError",
    "DockingOutcome",
    "DockingResult",
    "DockingSequence",
    "DockingServerParams",
    "DockingState",
    "DockingStep",
    "DockingWorld",
    "FrameUnavailable",
    "Obstacles",
    "Pose3D",
    "SimpleChargingDock",
    "SimpleChargingDockParams",
    "SmoothControlLawParams",
    "StagingGoal",
    "UndockRequest",
    "UndockingSequence",
    "dock_from_fields",
    "dock_pose_from_tag",
    "docks_from_yaml",
    "load_dock_file",
    "velocity_command",
]
