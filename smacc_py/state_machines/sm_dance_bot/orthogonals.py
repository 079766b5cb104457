"""The eight orthogonals of sm_dance_bot, created in SMACC2's order (SmDanceBot::onInitialize).

SMACC2's OrTimer holds a ``ClRosTimer`` ticking every 500 ms; here OrTimer holds ``ClRos2Timer`` and the
tick period belongs to the behavior (``CbTimerCountdownLoop(0.5)`` in StEventCountDown).
"""

from __future__ import annotations

from std_msgs.msg import String

from smacc_py.clients import ClRosPublisher
from smacc_py.clients.cl_nav2z import (
    ClNav2Z,
    CpGoalCheckerSwitcher,
    CpOdomTracker,
    CpPlannerSwitcher,
    CpPose,
    CpWaypointNavigator,
)
from smacc_py.clients.cl_ros2_timer import ClRos2Timer
from smacc_py.core import Orthogonal
from smacc_py.state_machines.sm_dance_bot.clients import (
    UPDATABLE_PUBLISHER_TOPIC,
    ClLED,
    ClLidarSensor,
    ClService3,
    ClStringPublisher,
    ClTemperatureSensor,
)
from smacc_py.state_machines.sm_dance_bot.waypoints import WAYPOINTS


class OrNavigation(Orthogonal):
    """ClNav2Z with pose, planner and goal-checker switchers, odom tracker and the waypoint navigator
    (SMACC2 also creates CpSlamToolbox: this stack localizes with AMCL on a known map)."""

    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")
        client.create_component(CpPlannerSwitcher)
        client.create_component(CpGoalCheckerSwitcher)
        client.create_component(CpOdomTracker)
        client.create_component(CpWaypointNavigator, WAYPOINTS)


class OrObstaclePerception(Orthogonal):
    """The lidar (ClLidarSensor on /scan, 10 s timeout)."""

    def on_initialize(self) -> None:
        self.create_client(ClLidarSensor)


class OrLED(Orthogonal):
    """The LED (ClLED)."""

    def on_initialize(self) -> None:
        self.create_client(ClLED)


class OrTemperatureSensor(Orthogonal):
    """The temperature sensor (ClTemperatureSensor on /temperature, 10 s timeout)."""

    def on_initialize(self) -> None:
        self.create_client(ClTemperatureSensor)


class OrStringPublisher(Orthogonal):
    """ClStringPublisher on /string_publisher_out."""

    def on_initialize(self) -> None:
        self.create_client(ClStringPublisher)


class OrService3(Orthogonal):
    """ClService3 on /service_node3."""

    def on_initialize(self) -> None:
        self.create_client(ClService3)


class OrTimer(Orthogonal):
    """ClRos2Timer (node clock: sim time under use_sim_time)."""

    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)


class OrUpdatablePublisher(Orthogonal):
    """ClRosPublisher of std_msgs/String on /updatable_string_publisher_out."""

    def on_initialize(self) -> None:
        self.create_client(ClRosPublisher, String, UPDATABLE_PUBLISHER_TOPIC)


ORTHOGONALS: tuple[type[Orthogonal], ...] = (
    OrNavigation, OrObstaclePerception, OrLED, OrTemperatureSensor, OrStringPublisher, OrService3, OrTimer,
    OrUpdatablePublisher,
)
