"""Docking behaviors on Nav2's docking_server (nav2_msgs DockRobot / UndockRobot): CbDockRobot and
CbUndockRobot.

SMACC2's cl_nav2z has no docking behaviors; these follow its action behaviors (CbNav2ZActionBase): the
goal goes through ClNav2Z (action keys ``dock_robot`` and ``undock_robot``, remappable with its
``action_names``), which posts its EvAction* events; the behavior posts ``EvCbSuccess[Cb, Or]`` or
``EvCbFailure[Cb, Or]`` with ``error_code`` (DockRobot's 901 DOCK_NOT_IN_DB, 902 DOCK_NOT_VALID, 903
FAILED_TO_STAGE, 904 FAILED_TO_DETECT_DOCK, 905 FAILED_TO_CONTROL, 906 FAILED_TO_CHARGE, 999 UNKNOWN;
UndockRobot's 902, 905 and 999), ``error_msg`` and ``result`` (DockRobot's carries ``num_retries``).
A goal still running when its state exits is cancelled, and the docking server stops the robot.
"""

from __future__ import annotations

import math
from typing import Any

from nav2_msgs.action import DockRobot, UndockRobot

from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.clients.cl_nav2z.client import DOCK_ROBOT, UNDOCK_ROBOT
from smacc_py.clients.cl_nav2z.cp_pose import make_pose_stamped


class CbDockRobot(CbNav2ZActionBase):
    """Dock at the docking server's dock ``dock_id``, or at ``dock_pose`` (x m, y m, yaw rad in
    ``frame_id``) of ``dock_type`` (empty: the server's only dock plugin).

    Args:
        dock_id: a dock of the server's database (its ``docks`` or ``dock_database``).
        dock_pose: instead of ``dock_id``.
        navigate_to_staging_pose: let the server navigate to the staging pose first (else the robot must
            already be there).
        max_staging_time: s the server may take to reach the staging pose.
    """

    def __init__(self, dock_id: str = "", *, dock_pose: tuple[float, float, float] | None = None,
                 frame_id: str = "map", dock_type: str = "", navigate_to_staging_pose: bool = True,
                 max_staging_time: float = 1000.0) -> None:
        if not isinstance(dock_id, str):
            raise TypeError(f"CbDockRobot: dock_id must be a str, got {dock_id!r}")
        if bool(dock_id) == (dock_pose is not None):
            raise ValueError(f"CbDockRobot: give exactly one of dock_id and dock_pose, got {dock_id!r} and "
                             f"{dock_pose!r}")
        if dock_pose is not None and (len(dock_pose) != 3 or not all(math.isfinite(v) for v in dock_pose)):
            raise ValueError(f"CbDockRobot: dock_pose must be 3 finite numbers (x, y, yaw), got "
                             f"{dock_pose!r}")
        if not max_staging_time > 0.0:
            raise ValueError(f"CbDockRobot: max_staging_time must be > 0 s, got {max_staging_time!r}")
        self.dock_id, self.dock_pose, self.frame_id = dock_id, dock_pose, frame_id
        self.dock_type, self.navigate_to_staging_pose = dock_type, navigate_to_staging_pose
        self.max_staging_time = float(max_staging_time)

    def make_goal(self) -> tuple[str, Any] | None:
        goal = DockRobot.Goal(navigate_to_staging_pose=self.navigate_to_staging_pose,
                              max_staging_time=self.max_staging_time)
        if self.dock_pose is None:
            goal.use_dock_id, goal.dock_id = True, self.dock_id
        else:
            goal.use_dock_id, goal.dock_type = False, self.dock_type
            goal.dock_pose = make_pose_stamped(self.frame_id, *self.dock_pose, stamp=self.sm.now())
        return DOCK_ROBOT, goal


class CbUndockRobot(CbNav2ZActionBase):
    """Undock: back to the staging pose of ``dock_type`` (empty: the dock the server docked at) within
    ``max_undocking_time`` s."""

    def __init__(self, dock_type: str = "", *, max_undocking_time: float = 30.0) -> None:
        if not isinstance(dock_type, str):
            raise TypeError(f"CbUndockRobot: dock_type must be a str, got {dock_type!r}")
        if not max_undocking_time > 0.0:
            raise ValueError(f"CbUndockRobot: max_undocking_time must be > 0 s, got {max_undocking_time!r}")
        self.dock_type, self.max_undocking_time = dock_type, float(max_undocking_time)

    def make_goal(self) -> tuple[str, Any] | None:
        goal = UndockRobot.Goal(dock_type=self.dock_type, max_undocking_time=self.max_undocking_time)
        return UNDOCK_ROBOT, goal
