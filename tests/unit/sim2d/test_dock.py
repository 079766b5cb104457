"""Docks: the body stands just beyond the docked robot's front, is solid and seen by the lidar; the
battery charges on the contacts (within tolerance, at rest) and nowhere else in a world with docks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim2d.core.battery import BatteryParams
from sim2d.core.collision import CollisionModel, CollisionParams
from sim2d.core.dock import CREATE3_DOCK, forward_reach
from sim2d.core.lidar import LidarParams, cast_rays
from sim2d.core.robot import TB4, WAFFLE, Pose2D, RobotModel
from tests.unit.sim2d.conftest import drive, room_with_docks, sim_in

DOCK = {"id": "home", "type": "create3_dock", "pose": [1.75, 0.0, 0.0]}   # 0.25 m from the east wall
CONTACT = Pose2D(1.75, 0.0, 0.0)


def test_forward_reach_is_the_footprint_front_over_the_yaw_tolerance() -> None:
    assert forward_reach(WAFFLE, 1e-9) == pytest.approx(0.069)          # -0.064 + 0.266 / 2
    assert forward_reach(TB4, 1e-9) == pytest.approx(0.171)             # a 16-gon edge faces +x
    # turned by 0.1 rad, the waffle's front corner reaches 0.069 cos 0.1 + 0.133 sin 0.1
    corner = 0.069 * math.cos(0.1) + 0.133 * math.sin(0.1)
    assert forward_reach(WAFFLE, 0.1) == pytest.approx(corner, abs=1e-6)


@pytest.mark.parametrize("robot", [WAFFLE, TB4], ids=lambda r: r.name)
def test_docked_robot_touches_nothing_but_a_little_further_hits_the_body(robot: RobotModel) -> None:
    world = room_with_docks(DOCK)
    (dock,) = world.docks
    model = CollisionModel(world.geometry.with_polygons((dock.body(robot),)), robot, CollisionParams())
    for yaw in (-0.1, 0.0, 0.1):                 # anywhere within the yaw tolerance
        assert not model.overlaps(Pose2D(CONTACT.x, CONTACT.y, yaw))
    face = dock.face_distance(robot)
    gap = face - forward_reach(robot, 1e-9)          # straight on: the clearance plus the yaw allowance
    assert gap < 0.025
    assert not model.overlaps(Pose2D(CONTACT.x + gap - 0.002, 0.0, 0.0))
    assert model.overlaps(Pose2D(CONTACT.x + gap + 0.002, 0.0, 0.0))
    assert face == pytest.approx(forward_reach(robot, 0.1) + CREATE3_DOCK.clearance)
    corners = dock.body(robot)
    assert corners[:, 0].min() == pytest.approx(CONTACT.x + face)
    assert corners[:, 0].max() - corners[:, 0].min() == pytest.approx(CREATE3_DOCK.body_depth)
    assert corners[:, 1].max() - corners[:, 1].min() == pytest.approx(CREATE3_DOCK.body_width)


def test_the_tb4_body_sits_where_the_create3_sim_puts_the_dock() -> None:
    # irobot_create_description: base_link 0.157 m from the dock link, its box 0.025..0.065 m beyond
    (dock,) = room_with_docks(DOCK).docks
    assert dock.face_distance(TB4) == pytest.approx(0.182, abs=0.003)


@pytest.mark.parametrize(("offset", "yaw", "expected"), [
    ((0.0, 0.0), 0.0, True), ((0.049, 0.0), 0.0, True), ((0.0, -0.049), 0.09, True),
    ((0.035, 0.035), 0.0, True), ((0.051, 0.0), 0.0, False), ((0.0, 0.0), 0.11, False),
    ((-0.04, 0.04), 0.0, False)])
def test_contact_within_the_tolerances(offset: tuple[float, float], yaw: float, expected: bool) -> None:
    (dock,) = room_with_docks(DOCK).docks
    assert (dock.contact_tolerance, dock.contact_yaw_tolerance) == (0.05, 0.1)
    assert dock.in_contact(Pose2D(CONTACT.x + offset[0], CONTACT.y + offset[1], yaw)) is expected


@pytest.mark.parametrize(("start", "charges"), [
    (CONTACT, True), (Pose2D(1.72, 0.02, -0.05), True),                  # on the contacts
    (Pose2D(1.69, 0.0, 0.0), False), (Pose2D(1.75, 0.0, 0.15), False),    # 6 cm short; turned 0.15 rad
])
def test_battery_charges_only_on_the_contacts_at_rest(start: Pose2D, charges: bool) -> None:
    sim = sim_in(room_with_docks(DOCK), start, battery=BatteryParams(initial_charge=0.5))
    drive(sim, 0.0, 0.0, 1.0)
    assert sim.battery.charging is charges
    assert (sim.battery.charge > 0.5) is charges
    assert (sim.battery.current > 0.5) is charges and (sim.battery.current < 0.0) is not charges
    assert (sim.docked is not None) is charges


def test_moving_on_the_dock_does_not_charge_and_a_world_with_docks_ignores_the_station() -> None:
    params = BatteryParams(initial_charge=0.5, station_x=0.0, station_y=0.0)
    sim = sim_in(room_with_docks(DOCK), Pose2D(1.73, 0.0, 0.0), battery=params)
    drive(sim, 0.0, 0.3, 0.5)                    # turning on the spot: on the contacts but not at rest
    assert not sim.battery.charging
    station = sim_in(room_with_docks(DOCK), Pose2D(0.0, 0.0, 0.0), battery=params)
    drive(station, 0.0, 0.0, 1.0)
    assert not station.battery.charging and station.battery.charge < 0.5
    old_rule = sim_in(room_with_docks(DOCK), Pose2D(0.0, 0.0, 0.0), battery=BatteryParams(
        initial_charge=0.5, station_x=0.0, station_y=0.0, charge_at="station"))
    drive(old_rule, 0.0, 0.0, 1.0)
    assert old_rule.battery.charging


def test_driving_onto_the_dock_charges_and_driving_into_it_is_a_collision() -> None:
    sim = sim_in(room_with_docks(DOCK), Pose2D(1.05, 0.0, 0.0), robot=TB4,
                 battery=BatteryParams(initial_charge=0.5))   # the staging pose, 0.7 m out
    while sim.pose.x < CONTACT.x - 0.01:
        sim.command(0.1, 0.0)
        sim.step()
    drive(sim, 0.0, 0.0, 0.5)
    assert sim.battery.charging and sim.collision_count == 0
    drive(sim, 0.2, 0.0, 2.0)                    # on into the dock's body
    assert sim.collision_count == 1
    assert sim.pose.x + TB4.footprint_radius == pytest.approx(CONTACT.x + sim.docks[0].face_distance(TB4),
                                                              abs=3e-3)


def test_lidar_sees_the_dock_but_the_world_geometry_has_no_dock() -> None:
    world = room_with_docks(DOCK)
    staging = world.docks[0].staging_pose()
    assert (staging.x, staging.y, staging.yaw) == pytest.approx((1.05, 0.0, 0.0))
    sim = sim_in(world, staging, lidar=LidarParams(noise_stddev=0.0))
    ranges = sim.scan()
    sensor_x = staging.x + WAFFLE.scan_offset[0]
    face_x = CONTACT.x + world.docks[0].face_distance(WAFFLE)
    assert ranges[0] == pytest.approx(face_x - sensor_x, abs=1e-9)
    beyond = cast_rays((sensor_x, 0.0), np.array([0.0]), world.geometry, 3.5)[0]
    assert beyond == pytest.approx(2.0 - sensor_x)                      # the map's world: only the wall


def test_shipped_dock_bodies_are_clear_of_the_walls_for_either_robot(tb3_world) -> None:
    for robot in (WAFFLE, TB4):
        (dock,) = tb3_world.docks
        assert not tb3_world.geometry.contains(dock.body(robot)).any()
