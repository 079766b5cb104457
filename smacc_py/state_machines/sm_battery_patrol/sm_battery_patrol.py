"""``SmBatteryPatrol``: the seed's battery-aware patrol as a hierarchical machine, and its parameters."""

from __future__ import annotations

import math
from dataclasses import dataclass

from smacc_py.clients.cl_nav2z.geometry import Pose2D
from smacc_py.core import SmaccStateMachineBase
from smacc_py.ros.context import ros_context
from smacc_py.ros.params import declare_dataclass_params
from smacc_py.state_machines.sm_battery_patrol import states as st
from smacc_py.state_machines.sm_battery_patrol.orthogonals import OrBattery, OrNavigation, OrTimer

LOCATION_NAMES = ("location1", "location2", "location3", "location4", "station")
RECHARGE_MODES = ("station", "dock")


@dataclass(frozen=True)
class SmBatteryPatrolParams:
    """ROS parameters of node ``SmBatteryPatrol`` (x, y in m, yaw in rad, map frame; charge 0..1; s).

    Attributes:
        initial_pose: AMCL's initial pose (the TurtleBot3 spawn pose).
        location1 .. location4, station: the seed project's locations (config/locations.yaml has the
            reachability figures).
        battery_topic: sensor_msgs/BatteryState topic (sim2d publishes /battery_state).
        low_threshold: a reading at or below it leaves the patrol for MsRecharge.
        charged_threshold: a reading at or above it, while parked, resumes the patrol.
        charge_timeout: sim s of charging without reaching the threshold before re-docking.
        recharge: ``station`` (drive to ``station`` and wait there, the seed's way) or ``dock`` (Nav2's
            DockRobot at ``dock_id``, charge, UndockRobot; needs a docking_server and a world with a dock).
        dock_id: the docking server's dock (its ``docks`` parameter) for ``recharge: dock``.
    """

    initial_pose: Pose2D = (-2.0, -0.5, 0.0)
    location1: Pose2D = (-1.03, -0.51, 0.0)
    location2: Pose2D = (-0.56, -1.03, 0.0)
    location3: Pose2D = (-1.43, -1.34, 3.14)
    location4: Pose2D = (-1.58, -1.48, 3.14)
    station: Pose2D = (-1.37, -0.82, 0.0)
    battery_topic: str = "/battery_state"
    low_threshold: float = 0.2
    charged_threshold: float = 0.95
    charge_timeout: float = 180.0
    recharge: str = "station"
    dock_id: str = "home_dock"

    def __post_init__(self) -> None:
        for name in ("initial_pose", *LOCATION_NAMES):
            value = getattr(self, name)
            if len(value) != 3 or not all(math.isfinite(v) for v in value):
                raise ValueError(f"SmBatteryPatrolParams.{name} must be 3 finite numbers (x, y, yaw), "
                                 f"got {value!r}")
        if not 0.0 <= self.low_threshold < self.charged_threshold <= 1.0:
            raise ValueError("SmBatteryPatrolParams: need 0 <= low_threshold < charged_threshold <= 1, got "
                             f"{self.low_threshold} and {self.charged_threshold}")
        if self.recharge not in RECHARGE_MODES:
            raise ValueError(f"SmBatteryPatrolParams.recharge must be one of {', '.join(RECHARGE_MODES)}, "
                             f"got {self.recharge!r}")
        if self.recharge == "dock" and not self.dock_id:
            raise ValueError("SmBatteryPatrolParams.dock_id must name a dock when recharge is 'dock'")
        if not self.charge_timeout > 0.0:
            raise ValueError(f"SmBatteryPatrolParams.charge_timeout must be > 0 s, got {self.charge_timeout}")

    def pose_of(self, location: str) -> Pose2D:
        """The pose of ``location1``..``location4`` or ``station``."""
        if location not in LOCATION_NAMES:
            raise ValueError(f"unknown location {location!r}; known: {', '.join(LOCATION_NAMES)}")
        pose: Pose2D = getattr(self, location)
        return pose


class SmBatteryPatrol(SmaccStateMachineBase):
    """Patrol location1..4; recharge when low; resume where it left off (deep history)."""

    initial_state = st.StStartup
    config: SmBatteryPatrolParams

    def on_initialize(self) -> None:
        self.config = declare_dataclass_params(ros_context(self).node, SmBatteryPatrolParams)
        self.create_orthogonal(OrNavigation)
        self.create_orthogonal(OrBattery)
        self.create_orthogonal(OrTimer)
