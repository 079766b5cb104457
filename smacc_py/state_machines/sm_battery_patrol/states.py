"""States of sm_battery_patrol.

    StStartup ──EvAllGo──▶ SsPatrol [StiGoToLocation1 → 2 → 3 → 4 → 1 ...]
    SsPatrol ──EvBatteryLow (SrConditional on EvBatteryState)──▶ MsRecharge [StiGoToStation → StiCharge]
    StiCharge ──EvBatteryCharged (SrConditional)──▶ History(SsPatrol): the interrupted location again

With the parameter ``recharge: dock`` the same low reading posts EvBatteryLowDock instead, and the
robot recharges as a TurtleBot4 does, on Nav2's docking_server:

    SsPatrol ──EvBatteryLowDock──▶ MsDockRecharge [StiDock → StiChargeDocked → StiUndock]
    StiUndock ──EvCbSuccess[CbUndockRobot]──▶ History(SsPatrol)

A failed navigation goal retries the same location (RETRY); charging that does not reach the
threshold within ``charge_timeout`` s re-docks (StiCharge → StiGoToStation, RETRY; on a dock:
StiChargeDocked → StiUndock, RETRY, and the still low battery docks again). A failed DockRobot or
UndockRobot goal is sent again (RETRY): the docking server has stopped the robot and tried its own
``max_retries`` first.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, ClassVar

from smacc_py.clients.cl_battery import (
    CbWaitBatteryState,
    ClBattery,
    EvBatteryCharged,
    EvBatteryLow,
    EvBatteryState,
    is_charged,
    is_low,
)
from smacc_py.clients.cl_nav2z import CbDockRobot, CbNavigateGlobalPosition, CbSetInitialPose, CbUndockRobot
from smacc_py.clients.cl_ros2_timer import CbTimerCountdownOnce
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvAllGo,
    EvCbFailure,
    EvCbSuccess,
    EvTimer,
    History,
    SmaccEvent,
    SmaccState,
    SrAllEventsGo,
    SrConditional,
    Transition,
)
from smacc_py.state_machines.sm_battery_patrol.orthogonals import OrBattery, OrNavigation, OrTimer

if TYPE_CHECKING:
    from smacc_py.state_machines.sm_battery_patrol.sm_battery_patrol import SmBatteryPatrol

log = logging.getLogger("sm_battery_patrol")

VISITS_KEY = "visits"  # global data: list of location names reached, in order
CYCLES_KEY = "patrol_cycles"  # global data: completed location1..4 rounds
RECHARGES_KEY = "recharges"
DOCKINGS_KEY = "dockings"  # global data: sim times (s) of the successful DockRobot goals
BATTERY_READING: type[SmaccEvent] = EvBatteryState[ClBattery, OrBattery]


class NEXT(SUCCESS):
    """The location was reached: go on to the next one."""


class RETRY(ABORT):
    """Try the same state again."""


class LOW_BATTERY(ABORT):  # noqa: N801  (tag name shown in introspection)
    """The battery ran low: leave the patrol to recharge."""


class RESUME(SUCCESS):
    """Charged: resume the patrol where it was interrupted (deep history)."""


class CHARGED(SUCCESS):
    """Charged on the dock: undock."""


class EvBatteryLowDock(SmaccEvent):
    """The battery ran low while the machine recharges on a dock (``recharge: dock``)."""


def _sm(state: SmaccState) -> SmBatteryPatrol:
    return state.sm  # type: ignore[return-value]


def _record(state: SmaccState, key: str, value: object) -> None:
    state.set_global_sm_data(key, [*state.get_global_sm_data(key, []), value])


class StStartup(SmaccState):
    """Set AMCL's initial pose and read the battery once; both done → patrol."""

    reactions = [
        Transition(EvAllGo, "SsPatrol", SUCCESS),
        Transition(EvCbFailure[CbSetInitialPose, OrNavigation], "StStartup", RETRY),
        Transition(EvCbFailure[CbWaitBatteryState, OrBattery], "StStartup", RETRY),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbSetInitialPose, -2.0, -0.5, 0.0)
        cls.configure_orthogonal(OrBattery, CbWaitBatteryState)
        cls.static_create_state_reactor(SrAllEventsGo, EvAllGo,
                                        [EvCbSuccess[CbSetInitialPose, OrNavigation],
                                         EvCbSuccess[CbWaitBatteryState, OrBattery]])

    def runtime_configure(self) -> None:
        behavior = self.get_client_behavior(OrNavigation, CbSetInitialPose)
        behavior.pose = _sm(self).config.initial_pose


class SsPatrol(SmaccState):
    """Visit location1..4 forever; a low battery reading leaves for MsRecharge."""

    inner_initial_state = "StiGoToLocation1"
    reactions = [Transition(EvBatteryLow, "MsRecharge", LOW_BATTERY),
                 Transition(EvBatteryLowDock, "MsDockRecharge", LOW_BATTERY)]

    @classmethod
    def static_configure(cls) -> None:
        cls.static_create_state_reactor(SrConditional, EvBatteryLow, [BATTERY_READING], is_low)

    def runtime_configure(self) -> None:
        if _sm(self).config.recharge == "dock":  # the low reading leads to the docking mode instead
            self.get_state_reactor(SrConditional).output_event = EvBatteryLowDock


class _GoTo(SmaccState):
    """Navigate to the pose named ``location`` in the machine's parameters."""

    location: ClassVar[str] = ""
    ends_cycle: ClassVar[bool] = False

    @classmethod
    def static_configure(cls) -> None:
        if cls.location:
            cls.configure_orthogonal(OrNavigation, CbNavigateGlobalPosition, 0.0, 0.0, 0.0)

    def runtime_configure(self) -> None:
        x, y, yaw = _sm(self).config.pose_of(self.location)
        self.get_client_behavior(OrNavigation, CbNavigateGlobalPosition).set_goal(x, y, yaw)

    def on_entry(self) -> None:
        log.info("%s: going to %s", type(self).__name__, self.location)

    def on_exit_NEXT(self) -> None:
        log.info("%s: reached %s", type(self).__name__, self.location)
        _record(self, VISITS_KEY, self.location)
        if self.ends_cycle:
            cycles = self.get_global_sm_data(CYCLES_KEY, 0) + 1
            self.set_global_sm_data(CYCLES_KEY, cycles)
            log.info("patrol cycle %d complete", cycles)

    def on_exit_RETRY(self) -> None:
        log.warning("%s: navigation to %s failed, retrying", type(self).__name__, self.location)


def _patrol_state(index: int) -> type[SmaccState]:
    following = f"StiGoToLocation{index % 4 + 1}"
    name = f"StiGoToLocation{index}"
    reactions = [
        Transition(EvCbSuccess[CbNavigateGlobalPosition, OrNavigation], following, NEXT),
        Transition(EvCbFailure[CbNavigateGlobalPosition, OrNavigation], name, RETRY),
    ]
    doc = f"Patrol leg to location{index}; then {following}."
    namespace = {"location": f"location{index}", "ends_cycle": index == 4, "reactions": reactions,
                 "__doc__": doc, "__module__": __name__, "__qualname__": name}
    return type(name, (_GoTo,), namespace, parent=SsPatrol)


StiGoToLocation1 = _patrol_state(1)
StiGoToLocation2 = _patrol_state(2)
StiGoToLocation3 = _patrol_state(3)
StiGoToLocation4 = _patrol_state(4)


class MsRecharge(SmaccState):
    """Recharge mode: drive to the station, then charge until the battery is full."""

    inner_initial_state = "StiGoToStation"

    def on_entry(self) -> None:
        log.warning("battery low: recharging")


class StiGoToStation(_GoTo, parent=MsRecharge):
    """Drive to the charging station."""

    location = "station"
    reactions = [
        Transition(EvCbSuccess[CbNavigateGlobalPosition, OrNavigation], "StiCharge", NEXT),
        Transition(EvCbFailure[CbNavigateGlobalPosition, OrNavigation], "StiGoToStation", RETRY),
    ]


class StiCharge(SmaccState, parent=MsRecharge):
    """Park at the station until a reading reaches the charged threshold (then resume the patrol)."""

    reactions = [
        Transition(EvBatteryCharged, History(SsPatrol), RESUME),
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StiGoToStation", RETRY),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, 180.0)
        cls.static_create_state_reactor(SrConditional, EvBatteryCharged, [BATTERY_READING], is_charged)

    def runtime_configure(self) -> None:
        self.get_client_behavior(OrTimer, CbTimerCountdownOnce).duration_s = _sm(self).config.charge_timeout

    def on_exit_RESUME(self) -> None:
        _record(self, RECHARGES_KEY, self.sm.now())
        log.info("charged: resuming the patrol")


class MsDockRecharge(SmaccState):
    """Recharge mode on a charging dock (``recharge: dock``): dock, charge, undock."""

    inner_initial_state = "StiDock"

    def on_entry(self) -> None:
        log.warning("battery low: recharging on dock %s", _sm(self).config.dock_id)


class StiDock(SmaccState, parent=MsDockRecharge):
    """DockRobot at the machine's ``dock_id``; the docking server navigates to its staging pose."""

    reactions = [
        Transition(EvCbSuccess[CbDockRobot, OrNavigation], "StiChargeDocked", NEXT),
        Transition(EvCbFailure[CbDockRobot, OrNavigation], "StiDock", RETRY),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbDockRobot, "dock")

    def runtime_configure(self) -> None:
        self.get_client_behavior(OrNavigation, CbDockRobot).dock_id = _sm(self).config.dock_id

    def on_exit_NEXT(self) -> None:
        _record(self, DOCKINGS_KEY, self.sm.now())
        log.info("docked at %s", _sm(self).config.dock_id)

    def on_exit_RETRY(self) -> None:
        log.warning("docking failed (docking_server's log says why): docking again")


class StiChargeDocked(SmaccState, parent=MsDockRecharge):
    """Wait on the dock until a reading reaches the charged threshold; then undock."""

    reactions = [
        Transition(EvBatteryCharged, "StiUndock", CHARGED),
        Transition(EvTimer[CbTimerCountdownOnce, OrTimer], "StiUndock", RETRY),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTimer, CbTimerCountdownOnce, 180.0)
        cls.static_create_state_reactor(SrConditional, EvBatteryCharged, [BATTERY_READING], is_charged)

    def runtime_configure(self) -> None:
        self.get_client_behavior(OrTimer, CbTimerCountdownOnce).duration_s = _sm(self).config.charge_timeout

    def on_exit_CHARGED(self) -> None:
        _record(self, RECHARGES_KEY, self.sm.now())

    def on_exit_RETRY(self) -> None:
        log.warning("not charged within charge_timeout: undocking (the low battery docks it again)")


class StiUndock(SmaccState, parent=MsDockRecharge):
    """UndockRobot back to the staging pose, then resume the patrol where it was interrupted (a
    charging timeout resumes it too: the next low reading docks again)."""

    reactions = [
        Transition(EvCbSuccess[CbUndockRobot, OrNavigation], History(SsPatrol), RESUME),
        Transition(EvCbFailure[CbUndockRobot, OrNavigation], "StiUndock", RETRY),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNavigation, CbUndockRobot)

    def on_exit_RESUME(self) -> None:
        log.info("undocked: resuming the patrol")
