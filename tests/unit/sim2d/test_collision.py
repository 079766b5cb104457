"""Collisions: the robot stops at walls and pillars, counts each contact once, never tunnels."""

from __future__ import annotations

from dataclasses import replace

import pytest

from sim2d.core.robot import WAFFLE, Pose2D
from tests.unit.sim2d.conftest import drive


def test_driving_into_a_pillar_stops_and_counts_one_collision(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, 0.0, 0.0))              # facing the pillar at (-1.1, 0.0)
    drive(sim, 0.26, 0.0, 8.0)                          # keeps pushing long after contact
    front = sim.pose.x + WAFFLE.footprint_offset_x + WAFFLE.footprint_length / 2
    assert front == pytest.approx(-1.1 - 0.15, abs=2e-3)
    assert sim.collision_count == 1
    events = sim.pop_collision_events()
    assert len(events) == 1
    assert (events[0].x, events[0].y) == pytest.approx((-1.25, 0.0), abs=0.01)
    assert sim.v == 0.0


def test_backing_off_and_hitting_again_counts_two(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, 0.0, 0.0))
    drive(sim, 0.26, 0.0, 5.0)
    drive(sim, -0.2, 0.0, 1.0)
    drive(sim, 0.26, 0.0, 3.0)
    assert sim.collision_count == 2


def test_free_driving_counts_nothing(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 0.0))
    drive(sim, 0.2, 0.0, 3.0)
    assert sim.collision_count == 0 and sim.pop_collision_events() == []


@pytest.mark.parametrize("speed", [1.0, 10.0, 100.0])
def test_no_tunnelling_at_any_speed(make_sim, speed: float) -> None:
    fast = replace(WAFFLE, max_linear_velocity=speed, max_linear_acceleration=1e9)
    sim = make_sim(Pose2D(-2.0, 0.0, 0.0), robot=fast, physics_step=0.02)
    drive(sim, speed, 0.0, 1.0)
    assert sim.pose.x < -1.1 - 0.15 - 0.066                      # still in front of the pillar
    assert sim.collision_count == 1


def test_wall_stops_the_robot(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 3.14159))          # facing the lower-left wall
    drive(sim, 0.26, 0.0, 6.0)
    assert sim.collision_count == 1
    assert not sim.collision.overlaps(sim.pose)


def test_teleport_into_an_obstacle_is_refused(make_sim) -> None:
    sim = make_sim()
    assert not sim.teleport(Pose2D(0.0, 0.0, 0.0))
    assert sim.pose == Pose2D(-2.0, -0.5, 0.0)
    assert sim.teleport(Pose2D(0.5, 0.5, 1.0))
    assert sim.pose == Pose2D(0.5, 0.5, 1.0)
