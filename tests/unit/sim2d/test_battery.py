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
    # turtlebot3_world has a dock, so "auto" would charge there: the seed's patrol overlay picks the station
    battery = BatteryParams(initial_charge=0.2, charge_per_second=0.05, charge_at="station")
    sim = make_sim(Pose2D(-1.37, -0.82, 0.0), battery=battery)
    drive(sim, 0.0, 0.0, 4.0)
    assert sim.battery.charge == pytest.approx(0.4, abs=1e-6)


def test_auto_charges_at_the_station_in_a_world_without_docks() -> None:
    params = BatteryParams(initial_charge=0.5, drain_per_second=0.0)
    battery = Battery(params, has_docks=False)
    battery.update(params.station_x, params.station_y, 0.0, 0.0, 0.0, 1.0)
    assert battery.charging and not battery.uses_docks
    docked_world = Battery(params, has_docks=True)          # a world with docks: only the docks charge
    docked_world.update(params.station_x, params.station_y, 0.0, 0.0, 0.0, 1.0)
    assert not docked_world.charging and docked_world.charge == 0.5
    docked_world.update(0.0, 0.0, 0.0, 0.0, 0.0, 1.0, on_dock=True)
    assert docked_world.charging and docked_world.charge == pytest.approx(0.52)
    station_only = Battery(BatteryParams(charge_at="station"), has_docks=True)
    station_only.update(5.0, 5.0, 0.0, 0.0, 0.0, 1.0, on_dock=True)
    assert not station_only.charging


def test_current_is_positive_while_charging_and_negative_while_draining() -> None:
    params = BatteryParams(initial_charge=0.5)
    battery = Battery(params, has_docks=True)
    battery.update(0.0, 0.0, 0.0, 0.0, 0.0, 0.005, on_dock=True)
    assert battery.current == params.charging_current > 0.5    # above Nav2's charging_threshold
    battery.update(0.0, 0.0, 0.2, 0.0, 0.001, 0.005, on_dock=True)   # moving on the dock: no charge
    drawn = (0.00011 * 0.001 + 0.00011 * 0.005) * 1.8 * 3600.0 / 0.005
    assert not battery.charging and battery.current == pytest.approx(-drawn)
    assert -1.0 < battery.current < -0.5                    # the waffle's figures: about 0.7 A idle
    empty = Battery(BatteryParams(initial_charge=0.0))
    empty.update(0.0, 0.0, 0.0, 0.0, 0.0, 0.005)
    assert empty.current == 0.0


def test_bad_charge_at_is_named() -> None:
    with pytest.raises(ValueError, match=r"battery\.charge_at: .*'dock'"):
        BatteryParams(charge_at="dock")


def test_bad_battery_figure_is_named() -> None:
    with pytest.raises(ValueError, match=r"battery\.initial_charge"):
        BatteryParams(initial_charge=1.5)
