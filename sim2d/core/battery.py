"""Battery as simulated state: drains while driving and idling, charges on a charger while at rest.

Charge is a fraction of full (0..1). Defaults follow the TurtleBot3 waffle: its 19.98 Wh LiPo pack
(11.1 V, 1.8 Ah) runs it for about 2 h, so 0.011 % per second (2.5 h idle) plus 0.011 % per metre
(driving at 0.26 m/s for 2 h is 1.9 km). The seed's battery patrol needs a battery that runs low
within a few rounds: config/sim2d_battery_patrol.yaml sets its accelerated figures (2 % per metre).

Charging adds ``charge_per_second`` while the robot rests (|v| < rest_linear_velocity,
|ω| < rest_angular_velocity) on a charger. Which chargers count is ``charge_at``:

- ``station``: within ``station_radius`` of the station, the seed project's (-1.37, -0.82);
- ``docks``: on the contacts of one of the world's docks (sim2d/core/dock.py), as a TurtleBot4 charges
  on its Create 3 dock;
- ``auto`` (default): the docks when the world declares any, else the station.

``current`` (A, BatteryState's sign convention) is +``charging_current`` while charging, also at
100 % (the dock keeps supplying the robot, and Nav2's SimpleChargingDock reads "charging" as a
current above its charging_threshold, 0.5 A, so a full robot still docks); otherwise minus the charge
actually drawn in the last step (about -0.7 A idle with the defaults; 0 once empty). At 0 the robot
cannot drive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

CHARGE_AT = ("auto", "station", "docks")
_SECONDS_PER_HOUR = 3600.0


@dataclass(frozen=True)
class BatteryParams:
    """Battery figures: fractions of full charge per metre/second, station pose (m) and radius (m),
    which chargers count (``charge_at``), the charger's current (A) and the pack (V, Ah)."""

    initial_charge: float = 1.0
    drain_per_meter: float = 0.00011
    drain_per_second: float = 0.00011
    charge_per_second: float = 0.02
    station_x: float = -1.37
    station_y: float = -0.82
    station_radius: float = 0.4  # goal tolerance 0.25 + goal moved off a pillar's band + localization error
    charge_at: str = "auto"
    charging_current: float = 1.8  # A: 1C for the 1.8 Ah pack (the reported figure; the charge itself
    #                                rises at charge_per_second, accelerated for the patrols)
    rest_linear_velocity: float = 0.01
    rest_angular_velocity: float = 0.05
    nominal_voltage: float = 11.1
    capacity_ah: float = 1.8

    def __post_init__(self) -> None:
        if not 0.0 <= self.initial_charge <= 1.0:
            raise ValueError(f"battery.initial_charge: must be in [0, 1], got {self.initial_charge}")
        for name in ("drain_per_meter", "drain_per_second", "charge_per_second", "station_radius",
                     "charging_current", "rest_linear_velocity", "rest_angular_velocity", "nominal_voltage",
                     "capacity_ah"):
            if getattr(self, name) < 0.0:
                raise ValueError(f"battery.{name}: must be >= 0, got {getattr(self, name)}")
        if self.charge_at not in CHARGE_AT:
            raise ValueError(f"battery.charge_at: must be one of {', '.join(CHARGE_AT)}, "
                             f"got {self.charge_at!r}")


class Battery:
    """Charge state updated once per physics step.

    ``has_docks`` says whether the world declares docks, which ``charge_at: auto`` follows.
    """

    def __init__(self, params: BatteryParams, has_docks: bool = False) -> None:
        self.params = params
        self.uses_docks = params.charge_at == "docks" or (params.charge_at == "auto" and has_docks)
        self.charge = params.initial_charge
        self.charging = False
        self.current = 0.0

    def reset(self) -> None:
        """Back to the initial charge."""
        self.charge = self.params.initial_charge
        self.charging = False
        self.current = 0.0

    @property
    def empty(self) -> bool:
        """True at 0 %: the drive refuses to move."""
        return self.charge <= 0.0

    @property
    def voltage(self) -> float:
        """Pack voltage (V): a simple linear sag from 100 % to 85 % of nominal at empty."""
        return self.params.nominal_voltage * (0.85 + 0.15 * self.charge)

    def update(self, x: float, y: float, v: float, w: float, distance: float, dt: float,
               on_dock: bool = False) -> None:
        """Advance ``dt`` (s) at pose (x, y) (m) with body velocity (v, w) after driving ``distance`` (m);
        ``on_dock``: base_link is on a dock's contacts (the simulator checks the docks)."""
        p = self.params
        resting = abs(v) < p.rest_linear_velocity and abs(w) < p.rest_angular_velocity
        on_charger = on_dock if self.uses_docks else \
            math.hypot(x - p.station_x, y - p.station_y) <= p.station_radius
        self.charging = resting and on_charger and p.charge_per_second > 0.0
        before = self.charge
        if self.charging:
            self.charge = min(1.0, self.charge + p.charge_per_second * dt)
            self.current = p.charging_current
        else:
            self.charge = max(0.0, self.charge - p.drain_per_meter * distance - p.drain_per_second * dt)
            drawn_ah = (before - self.charge) * p.capacity_ah
            self.current = -drawn_ah * _SECONDS_PER_HOUR / dt if dt > 0.0 else 0.0
