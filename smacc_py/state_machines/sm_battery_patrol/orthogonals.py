"""Orthogonals of sm_battery_patrol: navigation, battery, timer."""

from __future__ import annotations

from typing import TYPE_CHECKING

from smacc_py.clients.cl_battery import ClBattery, CpBatteryMonitor
from smacc_py.clients.cl_nav2z import ClNav2Z, CpAmcl, CpGoalCheckerSwitcher, CpPlannerSwitcher, CpPose
from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.core import Orthogonal

if TYPE_CHECKING:
    from smacc_py.state_machines.sm_battery_patrol.sm_battery_patrol import SmBatteryPatrol


class OrNavigation(Orthogonal):
    """ClNav2Z (navigate_to_pose) with the pose, selector and AMCL components."""

    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpPlannerSwitcher)
        client.create_component(CpGoalCheckerSwitcher)
        client.create_component(CpAmcl)


class OrBattery(Orthogonal):
    """ClBattery on the machine's battery topic; the monitor holds the machine's thresholds."""

    def on_initialize(self) -> None:
        sm: SmBatteryPatrol = self.sm  # type: ignore[assignment]
        client = self.create_client(ClBattery, sm.config.battery_topic)
        client.create_component(CpBatteryMonitor, sm.config.low_threshold, sm.config.charged_threshold)


class OrTimer(Orthogonal):
    """ClRos2Timer for the charging timeout."""

    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)
