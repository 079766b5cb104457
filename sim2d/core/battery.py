"""Battery as simulated state: drains while driving and idling, charges when resting at the station.

Charge is a fraction of full (0..1). Defaults follow the TurtleBot3 waffle: its 19.98 Wh LiPo pack
(11.1 V, 1.8 Ah) runs it for about 2 h, so 0.011 % per second (2.5 h idle) plus 0.011 % per metre
(driving at 0.26 m/s for 2 h is 1.9 km). The seed's battery patrol needs a battery that runs low
within a few rounds: config/sim2d_battery_patrol.yaml sets its accelerated figures (2 % per metre).
Charging adds ``charge_per_second`` while the robot rests (|v| < rest_linear_velocity,
|ω| < rest_angular_velocity) within ``station_radius`` of the station, the seed project's
(-1.37, -0.82). At 0 the robot cannot drive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class BatteryParams:
    """Battery figures: fractions of full charge per metre/second, station pose (m) and radius (m)."""

    initial_charge: float = 1.0
    drain_per_meter: float = 0.00011
    drain_per_second: float = 0.00011
    charge_per_second: float = 0.02
    station_x: float = -1.37
    station_y: float = -0.82
    station_radius: float = 0.4  # goal tolerance 0.25 + goal moved off a pillar's band + localization error
    rest_linear_velocity: float = 0.01
    rest_angular_velocity: float = 0.05
    nominal_voltage: float = 11.1
    capacity_ah: float = 1.8

    def __post_init__(self) -> None:
        if not 0.0 <= self.initial_charge <= 1.0:
            raise ValueError(f"battery.initial_charge: must be in [0, 1], got {self.initial_charge}")
        for name in ("drain_per_meter", "drain_per_second", "charge_per_second", "station_radius",
                     "rest_linear_velocity", "rest_angular_velocity", "nominal_voltage", "capacity_ah"):
            if getattr(self, name) < 0.0:
                raise ValueError(f"battery.{name}: must be >= 0, got {getattr(self, name)}")


class Battery:
    """Charge state updated once per physics step."""

    def __init__(self, params: BatteryParams) -> None:
        self.params = params
        self.charge = params.initial_charge
        self.charging = False

    def reset(self) -> None:
        """Back to the initial charge."""
        self.charge = self.params.initial_charge
        self.charging = False

    @property
    def empty(self) -> bool:
        """True at 0 %: the drive refuses to move."""
        return self.charge <= 0.0

    @property
    def voltage(self) -> float:
        """Pack voltage (V): a simple linear sag from 100 % to 85 % of nominal at empty."""
        return self.params.nominal_voltage * (0.85 + 0.15 * self.charge)

    def update(self, x: float, y: float, v: float, w: float, distance: float, dt: float) -> None:
        """Advance ``dt`` (s) at pose (x, y) (m) with body velocity (v, w) after driving ``distance`` (m)."""
        p = self.params
        resting = abs(v) < p.rest_linear_velocity and abs(w) < p.rest_angular_velocity
        docked = math.hypot(x - p.station_x, y - p.station_y) <= p.station_radius
        self.charging = resting and docked and p.charge_per_second > 0.0
        if self.charging:
            self.charge = min(1.0, self.charge + p.charge_per_second * dt)
        else:
            self.charge = max(0.0, self.charge - p.drain_per_meter * distance - p.drain_per_second * dt)
