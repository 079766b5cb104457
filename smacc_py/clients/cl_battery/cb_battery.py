"""Battery behaviors."""

from __future__ import annotations

from smacc_py.clients.cl_battery.client import ClBattery
from smacc_py.clients.cl_battery.cp_battery_monitor import CpBatteryMonitor
from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase


class CbWaitBatteryState(CbOutcomeBase):
    """Success (payload ``percentage``) once the battery has been read; failure after ``timeout_s``
    (machine clock, None: wait forever). Polls the monitor, so a reading that arrived before the
    state was entered counts."""

    strict_timeout = True  # fails once more than timeout_s has passed, as it always did

    def __init__(self, timeout_s: float | None = 30.0) -> None:
        self.timeout_s = timeout_s

    def start(self) -> None:
        self.requires_client(ClBattery)
        self._monitor = self.requires_component(CpBatteryMonitor)
        self.poll()

    def poll(self) -> None:
        percentage = self._monitor.percentage
        if percentage is not None:
            self.finish(True, percentage=percentage)

    def timeout_reason(self) -> str:
        return f"no battery reading within {self.timeout_s} s"
