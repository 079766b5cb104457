"""``ClBattery``: subscribes sensor_msgs/BatteryState and posts ``EvBatteryState[ClBattery, Or]``.

Each message updates the client's CpBatteryMonitor (created by the orthogonal, which knows the
thresholds) and is posted with the classified reading as payload (``percentage``, ``low``,
``charged``, ``charging``), so state reactors can turn it into EvBatteryLow / EvBatteryCharged.
"""

from __future__ import annotations

from sensor_msgs.msg import BatteryState

from smacc_py.clients.cl_battery.cp_battery_monitor import CpBatteryMonitor
from smacc_py.clients.cl_battery.events import EvBatteryState
from smacc_py.core import ISmaccClient
from smacc_py.ros.context import ros_context

BATTERY_TOPIC = "/battery_state"
CHARGING_STATUSES = (BatteryState.POWER_SUPPLY_STATUS_CHARGING, BatteryState.POWER_SUPPLY_STATUS_FULL)


class ClBattery(ISmaccClient):
    """Battery topic client; needs a CpBatteryMonitor component."""

    def __init__(self, topic: str = BATTERY_TOPIC) -> None:
        self.topic = topic

    def on_initialize(self) -> None:
        monitor = self.get_component(CpBatteryMonitor)
        if monitor is None:
            raise ValueError(f"ClBattery on {type(self.orthogonal).__name__}: create a CpBatteryMonitor "
                             "component (it holds the thresholds)")
        self.monitor = monitor
        ctx = ros_context(self.sm)
        self._sub = ctx.node.create_subscription(BatteryState, self.topic, self._on_message, 10)

    def _on_message(self, msg: BatteryState) -> None:
        reading = self.monitor.update(float(msg.percentage), msg.power_supply_status in CHARGING_STATUSES,
                                      self.sm.now())
        if reading is not None:
            event = self.own_event(EvBatteryState)(percentage=reading.percentage, low=reading.low,
                                                   charged=reading.charged, charging=reading.charging)
            self.post_event(event)
