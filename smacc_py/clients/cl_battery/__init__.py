"""cl_battery: a battery client (sensor_msgs/BatteryState, 0..1 charge) for smacc_py machines.

``ClBattery`` posts ``EvBatteryState[ClBattery, Or]`` per message; ``CpBatteryMonitor`` keeps the
latest reading classified as low/charged; ``CbWaitBatteryState`` waits for the first reading. A
machine turns readings into mission events with SrConditional reactors and the predicates
``is_low`` / ``is_charged``, posting ``EvBatteryLow`` / ``EvBatteryCharged``.
"""

from smacc_py.clients.cl_battery.cb_battery import CbWaitBatteryState
from smacc_py.clients.cl_battery.client import BATTERY_TOPIC, ClBattery
from smacc_py.clients.cl_battery.cp_battery_monitor import BatteryReading, CpBatteryMonitor
from smacc_py.clients.cl_battery.events import (
    EvBatteryCharged,
    EvBatteryLow,
    EvBatteryState,
    is_charged,
    is_low,
)

__all__ = [
    "BATTERY_TOPIC",
    "BatteryReading",
    "CbWaitBatteryState",
    "ClBattery",
    "CpBatteryMonitor",
    "EvBatteryCharged",
    "EvBatteryLow",
    "EvBatteryState",
    "is_charged",
    "is_low",
]
