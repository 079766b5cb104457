"""Battery drains per metre and per second, charges at the station, and stops the robot when empty."""

from __future__ import annotations

import pytest

from sim2d.core.battery import Battery, BatteryParams
from sim2d.core.robot import Pose2D
from tests.unit.sim2d.conftest import drive


def test_drains_per_second_and_per_metre() -> None:
    battery = Battery(BatteryParams(drain_per_meter=0.05, drain_per_second=0.001))
    battery.update(0.0, 0.0, 0.0, 0.0, distance=0.0, dt=10.0)
    assert battery.charge == pytest.approx(0.99)
    battery.update(0.0, 0.0, 0.2, 0.0, distance=2.0, dt=0.0)
    assert battery.charge == pytest.approx(0.89)


def test_charges_only_when_resting_at_the_station() -> None:
    params = BatteryParams(initial_charge=0.5, charge_per_second=0.01, drain_per_second=0.0)
    battery = Battery(params)
    battery.update(params.station_x + 0.1, params.station_y, 0.0, 0.0, 0.0, 10.0)
    assert battery.charge == pytest.approx(0.6) and battery.charging
    battery.update(params.station_x, params.station_y, 0.2, 0.0, 0.0, 10.0)     # moving: no charge
    assert battery.charge == pytest.approx(0.6) and not battery.charging
    battery.update(params.station_x + 1.0, params.station_y, 0.0, 0.0, 0.0, 10.0)  # too far
    assert battery.charge == pytest.approx(0.6)
    battery.update(params.station_x, params.station_y, 0.0, 0.0, 0.0, 100.0)
    assert battery.charge == 1.0


def test_simulated_drive_drains_by_distance(make_sim) -> None:
    sim = make_sim(battery=BatteryParams(drain_per_meter=0.1, drain_per_second=0.0))
    drive(sim, 0.2, 0.0, 5.0)
    assert sim.battery.charge == pytest.approx(1.0 - 0.1 * (sim.pose.x + 2.0), abs=1e-9)


def test_empty_battery_cannot_drive(make_sim) -> None:
    sim = make_sim(battery=BatteryParams(initial_charge=0.0))
    drive(sim, 0.2, 0.5, 2.0)
    assert sim.pose == Pose2D(-2.0, -0.5, 0.0)


def test_robot_charges_when_parked_at_the_station(make_sim) -> None:
    battery = BatteryParams(initial_charge=0.2, charge_per_second=0.05)
    sim = make_sim(Pose2D(-1.37, -0.82, 0.0), battery=battery)
    drive(sim, 0.0, 0.0, 4.0)
    assert sim.battery.charge == pytest.approx(0.4, abs=1e-6)


def test_bad_battery_figure_is_named() -> None:
    with pytest.raises(ValueError, match=r"battery\.initial_charge"):
        BatteryParams(initial_charge=1.5)
