"""Battery behaviors."""

from __future__ import annotations

from smacc_py.clients.cl_battery.client import ClBattery
from smacc_py.clients.cl_battery.cp_battery_monitor import CpBatteryMonitor
from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior


class CbWaitBatteryState(SmaccClientBehavior, ISmaccUpdatable):
    """Success (payload ``percentage``) once the battery has been read; failure after ``timeout_s``
    (machine clock, None: wait forever). Polls the monitor, so a reading that arrived before the
    state was entered counts."""

    def __init__(self, timeout_s: float | None = 30.0) -> None:
        self.timeout_s = timeout_s
        self._done = False

    def on_entry(self) -> None:
        self.requires_client(ClBattery)
        self._monitor = self.requires_component(CpBatteryMonitor)
        self._start_s = self.sm.now()
        self.update()

    def update(self) -> None:
        if self._done:
            return
        percentage = self._monitor.percentage
        if percentage is not None:
            self._done = True
            self.post_success_event(percentage=percentage)
        elif self.timeout_s is not None and self.sm.now() - self._start_s > self.timeout_s:
            self._done = True
            self.post_failure_event(reason=f"no battery reading within {self.timeout_s} s")
