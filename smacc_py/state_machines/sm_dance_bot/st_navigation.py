"""sm_dance_bot's sensor, countdown and waypoint states (SMACC2: st_acquire_sensors.hpp,
st_event_count_down.hpp, st_navigate_to_waypoints_x.hpp, st_navigate_to_waypoint_1.hpp).

* ``StAcquireSensors``: lidar, temperature and robot pose must all report (SrAllEventsGo); meanwhile it
  greets on /string_publisher_out (on exit), switches service3 on and publishes on the updatable
  publisher. The temperature behavior runs on MsDanceBotRunMode (see modestates.py); its messages are
  the reactor's input all the same.
* ``StEventCountDown``: SrEventCountdown(5) over the timer's ticks (CbTimerCountdownLoop, 0.5 s of sim
  time, upstream's ClRosTimer period), then the waypoints.
* ``StNavigateToWaypointsX``: the next waypoint of CpWaypointNavigator; reaching waypoint i posts
  ``EvWaypoint<i>`` and picks the next pattern. Upstream's EvWaypoint4 returns here; it goes to
  StNavigateForward2 instead (upstream, no transition reaches StNavigateForward2), then back here by way
  of StRotateDegrees5.
* ``StNavigateToWaypoint1``: home (upstream: (0, 0), the centre pillar here), then StFinalState
  (upstream: back to StNavigateToWaypointsX with an exhausted waypoint list); failure ends with ABORT.
"""

from __future__ import annotations

from std_msgs.msg import String

from smacc_py.clients import CbDefaultPublishLoop
from smacc_py.clients.cl_nav2z import (
    CbNavigateGlobalPosition,
    CbNavigateNextWaypoint,
    CbWaitPose,
    ClNav2Z,
    CpWaypointNavigator,
)
from smacc_py.clients.cl_ros2_timer import CbTimerCountdownLoop
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvAllGo,
    EvCbFailure,
    EvCbSuccess,
    EvCountdownEnd,
    EvTimer,
    EvTopicMessage,
    SmaccEvent,
    SmaccState,
    SrAllEventsGo,
    SrEventCountdown,
    Transition,
    waypoint_event,
)
from smacc_py.state_machines.sm_dance_bot import waypoints as wp
from smacc_py.state_machines.sm_dance_bot.clients import (
    CbConditionTemperatureSensor,
    CbLEDOn,
    CbLidarSensor,
    CbService3,
    CbStringPublisher,
    Service3Command,
)
from smacc_py.state_machines.sm_dance_bot.modestates import (
    EvGlobalError,
    MsDanceBotRecoveryMode,
    MsDanceBotRunMode,
    StFinalState,
)
from smacc_py.state_machines.sm_dance_bot.orthogonals import (
    OrLED,
    OrNavigation,
    OrObstaclePerception,
    OrService3,
    OrStringPublisher,
    OrTemperatureSensor,
    OrTimer,
    OrUpdatablePublisher,
)

COUNTDOWN_TICKS = 5  # SrEventCountdown(5), upstream's
TICK_S = 0.5  # s of sim time between timer events (upstream's ClRosTimer period)


class ON_SENSORS_AVAILABLE(SUCCESS):  # noqa: N801  (SMACC2 tag name)
    """Lidar, temperature and pose all reported."""


class StAcquireSensors(SmaccState, parent=MsDanceBotRunMode):
    """Wait until lidar, temperature and the robot pose have all reported."""

    reactions = [
        Transition(EvAllGo, "StEventCountDown", ON_SENSORS_AVAILABLE),
        Transition(EvGlobalError, MsDanceBotRecoveryMode),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrObstaclePerception, CbLidarSensor)
        cls.configure_orthogonal(OrStringPublisher, CbStringPublisher, "Hello World!")
        cls.configure_orthogonal(OrService3, CbService3, Service3Command.SERVICE3_ON)
        cls.configure_orthogonal(OrUpdatablePublisher, CbDefaultPublishLoop, String(data="sm_dance_bot"), 1.0)
        cls.configure_orthogonal(OrNavigation, CbWaitPose)
        cls.static_create_state_reactor(
            SrAllEventsGo, EvAllGo[SrAllEventsGo, cls],
            [EvTopicMessage[CbLidarSensor, OrObstaclePerception],
             EvTopicMessage[CbConditionTemperatureSensor, OrTemperatureSensor],
             EvCbSuccess[CbWaitPose, OrNavigation]],
        )


class StEventCountDown(SmaccState, parent=MsDanceBotRunMode):
    """Count five timer ticks, then go to the waypoints."""

    reactions = [
        Transition(EvCountdownEnd, "StNavigateToWaypointsX"),
        Transition(EvGlobalError, MsDanceBotRecoveryMode),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownLoop, TICK_S)
        cls.static_create_state_reactor(SrEventCountdown, EvCountdownEnd[SrEventCountdown, cls],
                                        [EvTimer[CbTimerCountdownLoop, OrTimer]], COUNTDOWN_TICKS)


class TRANSITION_1(SUCCESS):  # noqa: N801
    """Waypoint 0 reached: radial pattern 1."""


class TRANSITION_2(SUCCESS):  # noqa: N801
    """Waypoint 1 reached: radial pattern 2."""


class TRANSITION_3(SUCCESS):  # noqa: N801
    """Waypoint 2 reached: radial pattern 3."""


class TRANSITION_4(SUCCESS):  # noqa: N801
    """Waypoint 3 reached: F pattern."""


class TRANSITION_5(SUCCESS):  # noqa: N801
    """Waypoint 4 reached: a short forward motion."""


class TRANSITION_6(SUCCESS):  # noqa: N801
    """Waypoint 5 reached: on to the next waypoint."""


class TRANSITION_7(SUCCESS):  # noqa: N801
    """Waypoint 6 reached: S pattern."""


def _reached(index: int) -> type:
    return waypoint_event(index)[ClNav2Z, OrNavigation]


class EvWaypointsExhausted(SmaccEvent):
    """StNavigateToWaypointsX was entered with no waypoint left (new; parameter: the state)."""

    param_names = ("state",)


class ALL_VISITED(SUCCESS):  # noqa: N801
    """No waypoint left: go home."""


class StNavigateToWaypointsX(SmaccState, parent=MsDanceBotRunMode):
    """Navigate to the next waypoint; which one was reached picks the next pattern. Entered with no
    waypoint left (a failure after the last pattern leads here), it goes home instead of failing for
    ever (upstream: CbNavigateNextWaypoint fails and the ABORT self-transition repeats)."""

    reactions = [
        Transition(EvWaypointsExhausted, "StNavigateToWaypoint1", ALL_VISITED),
        Transition(_reached(0), "SsRadialPattern1", TRANSITION_1),
        Transition(_reached(1), "SsRadialPattern2", TRANSITION_2),
        Transition(_reached(2), "SsRadialPattern3", TRANSITION_3),
        Transition(_reached(3), "SsFPattern1", TRANSITION_4),
        Transition(_reached(4), "StNavigateForward2", TRANSITION_5),
        Transition(_reached(5), "StNavigateToWaypointsX", TRANSITION_6),
        Transition(_reached(6), "SsSPattern1", TRANSITION_7),
        Transition(EvCbFailure[CbNavigateNextWaypoint, OrNavigation], "StNavigateToWaypointsX", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrLED, CbLEDOn)
        cls.configure_orthogonal(OrNavigation, CbNavigateNextWaypoint)
        cls.configure_orthogonal(OrObstaclePerception, CbLidarSensor)

    def on_entry(self) -> None:
        if self.requires_component(CpWaypointNavigator).current() is None:
            self.post_event(EvWaypointsExhausted[type(self)])


class StNavigateToWaypoint1(SmaccState, parent=MsDanceBotRunMode):
    """Drive home and say "All Done!" (on exit)."""

    reactions = [
        Transition(EvCbSuccess[CbNavigateGlobalPosition, OrNavigation], StFinalState),
        Transition(EvCbFailure[CbNavigateGlobalPosition, OrNavigation], StFinalState, ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, *wp.HOME)
        cls.configure_orthogonal(OrLED, CbLEDOn)
        cls.configure_orthogonal(OrStringPublisher, CbStringPublisher, "All Done!")
        cls.configure_orthogonal(OrObstaclePerception, CbLidarSensor)
