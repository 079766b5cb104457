"""docking_server's own parameters (the dock plugins and the controller have theirs)."""

from __future__ import annotations

import math
from dataclasses import dataclass

#: m the approach target lies beyond the dock along its heading (a constant in Nav2's approachDock):
#: the smooth control law gets jittery at the end of its spiral, so the robot aims past the dock and
#: is stopped by "docked" (or by the dock itself) before it gets there.
APPROACH_PROJECTION = 0.25


@dataclass(frozen=True)
class DockingServerParams:
    """docking_server parameters: Nav2 Jazzy's names and code defaults.

    Nav2's nav2_params.yaml sets ``undock_angular_tolerance: 0.1``; the code default is 0.05 rad. The
    dock database (``dock_plugins``, ``docks``, ``dock_database``) is read by the node. Units: Hz, s, m,
    rad; ``dock_prestaging_tolerance`` is Nav2's l2 norm over (x m, y m, yaw rad).
    """

    controller_frequency: float = 50.0
    initial_perception_timeout: float = 5.0
    wait_charge_timeout: float = 5.0
    dock_approach_timeout: float = 30.0
    undock_linear_tolerance: float = 0.05
    undock_angular_tolerance: float = 0.05
    max_retries: int = 3
    base_frame: str = "base_link"
    fixed_frame: str = "odom"
    dock_backwards: bool = False
    dock_prestaging_tolerance: float = 0.5
    navigator_bt_xml: str = ""
    action_server_result_timeout: float = 10.0
    enable_stamped_cmd_vel: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.controller_frequency) and self.controller_frequency > 0.0):
            raise ValueError(f"controller_frequency must be > 0 Hz, got {self.controller_frequency}")
        for name in ("initial_perception_timeout", "wait_charge_timeout", "dock_approach_timeout",
                     "dock_prestaging_tolerance", "action_server_result_timeout"):
            value = getattr(self, name)
            if not value >= 0.0:
                raise ValueError(f"{name} must be >= 0, got {value}")
        for name in ("undock_linear_tolerance", "undock_angular_tolerance"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ValueError(f"{name} must be > 0, got {value}")
        if self.max_retries < 0:
            raise ValueError(f"max_retries must be >= 0, got {self.max_retries}")
        if not self.base_frame.strip("/") or not self.fixed_frame.strip("/"):
            raise ValueError(f"base_frame and fixed_frame must name frames, got '{self.base_frame}' and "
                             f"'{self.fixed_frame}'")
