"""sm_battery_patrol: the seed project's battery-aware patrol as a hierarchical smacc_py machine.

StStartup (AMCL initial pose + first battery reading) → SsPatrol (StiGoToLocation1..4, round and
round) → on a low reading MsRecharge (StiGoToStation → StiCharge) → on a charged reading back to
``History(SsPatrol)``, i.e. the location whose leg was interrupted. With ``recharge: dock`` the recharge
mode is MsDockRecharge instead (StiDock → StiChargeDocked → StiUndock: Nav2's DockRobot and UndockRobot
through CbDockRobot / CbUndockRobot). Battery readings come from
/battery_state through cl_battery; SrConditional reactors post EvBatteryLow / EvBatteryCharged.
Unlike the seed's tree, which starts the patrol over at location1, the patrol resumes.

Run: ``smacc-run sm_battery_patrol --ros-args --params-file config/sm_battery_patrol.yaml`` against a
running stack, or the whole thing with ``sm-battery-patrol`` (demo.py).
"""

from smacc_py.state_machines.sm_battery_patrol.sm_battery_patrol import SmBatteryPatrol, SmBatteryPatrolParams
from smacc_py.state_machines.sm_battery_patrol.states import (
    CHARGED,
    CYCLES_KEY,
    DOCKINGS_KEY,
    LOW_BATTERY,
    NEXT,
    RECHARGES_KEY,
    RESUME,
    RETRY,
    VISITS_KEY,
    MsDockRecharge,
    MsRecharge,
    SsPatrol,
    StiCharge,
    StiChargeDocked,
    StiDock,
    StiGoToLocation1,
    StiGoToLocation2,
    StiGoToLocation3,
    StiGoToLocation4,
    StiGoToStation,
    StiUndock,
    StStartup,
)

STATE_MACHINE = SmBatteryPatrol

__all__ = [
    "CHARGED",
    "CYCLES_KEY",
    "DOCKINGS_KEY",
    "LOW_BATTERY",
    "NEXT",
    "RECHARGES_KEY",
    "RESUME",
    "RETRY",
    "STATE_MACHINE",
    "VISITS_KEY",
    "MsDockRecharge",
    "MsRecharge",
    "SmBatteryPatrol",
    "SmBatteryPatrolParams",
    "SsPatrol",
    "StStartup",
    "StiCharge",
    "StiChargeDocked",
    "StiDock",
    "StiGoToLocation1",
    "StiGoToLocation2",
    "StiGoToLocation3",
    "StiGoToLocation4",
    "StiGoToStation",
    "StiUndock",
]
