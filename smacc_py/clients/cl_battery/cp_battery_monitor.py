"""``CpBatteryMonitor``: the latest battery reading and what it means for the mission.

Thresholds are fractions of a full charge, as sensor_msgs/BatteryState.percentage (0..1): a reading
at or below ``low_threshold`` is low, at or above ``charged_threshold`` is charged. The component
holds no ROS objects (ClBattery feeds it), so a machine's logic can be tested with plain calls.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

from smacc_py.core import ISmaccComponent


@dataclass(frozen=True)
class BatteryReading:
    """One reading: charge (0..1), whether it is low or charged, and whether the robot is charging."""

    percentage: float
    low: bool
    charged: bool
    charging: bool
    stamp_s: float


class CpBatteryMonitor(ISmaccComponent):
    """Latest reading of ClBattery's topic, classified with the machine's thresholds."""

    def __init__(self, low_threshold: float = 0.2, charged_threshold: float = 0.95) -> None:
        if not 0.0 <= low_threshold < charged_threshold <= 1.0:
            raise ValueError("CpBatteryMonitor: need 0 <= low_threshold < charged_threshold <= 1, got "
                             f"low_threshold={low_threshold}, charged_threshold={charged_threshold}")
        self.low_threshold = low_threshold
        self.charged_threshold = charged_threshold
        self._lock = threading.Lock()
        self._reading: BatteryReading | None = None

    def update(self, percentage: float, charging: bool, stamp_s: float) -> BatteryReading | None:
        """Classify and keep a reading; None (and nothing kept) when ``percentage`` is NaN (unknown)."""
        if not math.isfinite(percentage):
            return None
        value = min(1.0, max(0.0, percentage))
        reading = BatteryReading(value, value <= self.low_threshold, value >= self.charged_threshold,
                                 charging, stamp_s)
        with self._lock:
            self._reading = reading
        return reading

    @property
    def reading(self) -> BatteryReading | None:
        """The latest reading, or None before the first message."""
        with self._lock:
            return self._reading

    @property
    def percentage(self) -> float | None:
        """The latest charge (0..1), or None."""
        reading = self.reading
        return None if reading is None else reading.percentage
