"""Battery sources behind the seed's four battery nodes (IsBatteryLow, DecrementBattery,
CheckBattery, RechargeBattery). Pure: the node feeds ``TopicBattery`` from /battery_state.

``counter`` is the seed's battery_behavior.cpp, minus its process-global static: 100 at start,
DecrementBattery −25 (clamped at 0), IsBatteryLow iff 0, CheckBattery iff > 0, RechargeBattery
sets 100 at once. Its cycle is the seed's: location1..4 (75, 50, 25, 0), CheckBattery fails, the
root returns FAILURE; the next run goes to the station, waits, recharges and returns SUCCESS.

``topic`` reads the simulator's charge (sensor_msgs/BatteryState.percentage, 0..1) instead:

* IsBatteryLow: SUCCESS iff charge ≤ ``low_threshold``;
* DecrementBattery: SUCCESS without effect (the simulator drains: per metre driven and per second);
* CheckBattery: SUCCESS iff charge > ``low_threshold`` (the same line, so exactly one of the two
  branches applies at any instant);
* RechargeBattery: RUNNING while the robot rests at the station and the simulator charges it;
  SUCCESS once charge ≥ ``charged_threshold``; FAILURE after ``recharge_timeout`` s (sim time)
  and on no data.

With these, the tree visits the seed's order whenever the threshold is crossed on the leg to
location4: locations 1..4, CheckBattery fails, root FAILURE, station, WaitSeconds (charging already
runs), RechargeBattery until charged, root SUCCESS. When it is crossed earlier, the patrol is cut
short at the first location reached below the threshold and, as in the seed's tree (it has no
memory), restarts at location1 after recharging; sm_battery_patrol resumes instead.
"""

from __future__ import annotations

import enum
import math
import threading
from dataclasses import dataclass
from typing import Protocol

SEED_FULL = 100
SEED_STEP = 25


class RechargeState(enum.Enum):
    """Progress of a recharge."""

    CHARGING = "charging"
    CHARGED = "charged"
    FAILED = "failed"


class BatterySource(Protocol):
    """What the battery nodes ask; ``now`` is the tree's time (s)."""

    def ready(self) -> bool:
        """True once the source has a level (the node does not tick before)."""

    def is_low(self) -> bool:
        """IsBatteryLow."""

    def has_charge(self) -> bool:
        """CheckBattery."""

    def decrement(self) -> None:
        """DecrementBattery."""

    def start_recharge(self, now: float) -> RechargeState:
        """RechargeBattery's first tick."""

    def poll_recharge(self, now: float) -> RechargeState:
        """RechargeBattery's later ticks."""

    def describe(self) -> str:
        """The level for logs, e.g. ``50 %``."""


class CounterBattery:
    """The seed's integer counter (percent)."""

    def __init__(self, level: int = SEED_FULL, step: int = SEED_STEP) -> None:
        self.level = level
        self.step = step

    def ready(self) -> bool:
        return True

    def is_low(self) -> bool:
        return self.level == 0

    def has_charge(self) -> bool:
        return self.level > 0

    def decrement(self) -> None:
        self.level = max(0, self.level - self.step)

    def start_recharge(self, now: float) -> RechargeState:
        self.level = SEED_FULL
        return RechargeState.CHARGED

    def poll_recharge(self, now: float) -> RechargeState:
        return RechargeState.CHARGED

    def describe(self) -> str:
        return f"{self.level} % (counter)"


@dataclass(frozen=True)
class TopicBatteryParams:
    """Thresholds (fractions of a full charge, as BatteryState.percentage) and the timeout (s)."""

    low_threshold: float = 0.2
    charged_threshold: float = 0.95
    recharge_timeout: float = 120.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.low_threshold < self.charged_threshold <= 1.0:
            raise ValueError("battery thresholds must satisfy 0 <= low_threshold < charged_threshold <= 1, "
                             "got "
                             f"low_threshold={self.low_threshold}, "
                             f"charged_threshold={self.charged_threshold}")
        if not self.recharge_timeout > 0.0:
            raise ValueError(f"recharge_timeout must be > 0 s, got {self.recharge_timeout}")


class TopicBattery:
    """The latest simulator charge; ``update`` is called from the subscription (thread-safe)."""

    def __init__(self, params: TopicBatteryParams | None = None) -> None:
        self.params = params or TopicBatteryParams()
        self._lock = threading.Lock()
        self._charge: float | None = None
        self._deadline = math.inf

    def update(self, percentage: float) -> None:
        """A new BatteryState.percentage (0..1; NaN means unknown and is ignored)."""
        if math.isfinite(percentage):
            with self._lock:
                self._charge = min(1.0, max(0.0, percentage))

    @property
    def charge(self) -> float | None:
        """Latest charge (0..1) or None before the first message."""
        with self._lock:
            return self._charge

    def ready(self) -> bool:
        return self.charge is not None

    def is_low(self) -> bool:
        charge = self.charge
        return charge is not None and charge <= self.params.low_threshold

    def has_charge(self) -> bool:
        charge = self.charge
        return charge is not None and charge > self.params.low_threshold

    def decrement(self) -> None:
        """The simulator drains the battery itself."""

    def start_recharge(self, now: float) -> RechargeState:
        self._deadline = now + self.params.recharge_timeout
        return self.poll_recharge(now)

    def poll_recharge(self, now: float) -> RechargeState:
        charge = self.charge
        if charge is not None and charge >= self.params.charged_threshold:
            return RechargeState.CHARGED
        if charge is None or now > self._deadline:
            return RechargeState.FAILED
        return RechargeState.CHARGING

    def describe(self) -> str:
        charge = self.charge
        return "no /battery_state yet" if charge is None else f"{100.0 * charge:.1f} % (topic)"
