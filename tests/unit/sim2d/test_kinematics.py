"""Differential-drive motion: analytic lines and arcs, limits, watchdog."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from sim2d.core.robot import BURGER, WAFFLE, Pose2D, integrate, limit_velocity, robot_model
from tests.unit.sim2d.conftest import drive

FAST = replace(WAFFLE, max_linear_acceleration=1e6, max_angular_acceleration=1e6)


def test_straight_line_matches_analytic_distance_with_acceleration_ramp(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 0.0))
    drive(sim, 0.2, 0.0, 1.0)
    ramp = 0.2 / WAFFLE.max_linear_acceleration                    # 0.2 s at 1 m/s²
    expected = 0.5 * 0.2 * ramp + 0.2 * (1.0 - ramp)
    assert sim.pose.x == pytest.approx(-2.0 + expected, abs=1e-9)
    assert sim.pose.y == pytest.approx(-0.5, abs=1e-12) and sim.pose.yaw == pytest.approx(0.0, abs=1e-12)


def test_arc_matches_the_circle(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -0.5, 0.0), robot=FAST)
    v, w, t = 0.2, 0.5, 2.0
    drive(sim, v, w, t)
    radius = v / w
    angle = w * (t - 0.5 * sim.params.physics_step)   # the first step averages rest and full speed
    assert sim.pose.yaw == pytest.approx(angle, abs=1e-9)
    assert sim.pose.x == pytest.approx(-2.0 + radius * math.sin(angle), abs=1e-9)
    assert sim.pose.y == pytest.approx(-0.5 + radius * (1.0 - math.cos(angle)), abs=1e-9)


def test_commands_beyond_limits_are_clamped(make_sim) -> None:
    for model in (WAFFLE, BURGER):
        sim = make_sim(robot=model)
        drive(sim, 5.0, -9.0, 2.0)
        assert sim.v == pytest.approx(model.max_linear_velocity)
        assert sim.w == pytest.approx(-model.max_angular_velocity)


def test_acceleration_limits_hold_every_step() -> None:
    dt, v, w = 0.005, 0.0, 0.0
    for target in (0.26, -0.26, 0.0):
        for _ in range(200):
            v_new, w_new = limit_velocity(WAFFLE, v, w, target, -target * 5, dt)
            assert abs(v_new - v) <= WAFFLE.max_linear_acceleration * dt + 1e-12
            assert abs(w_new - w) <= WAFFLE.max_angular_acceleration * dt + 1e-12
            v, w = v_new, w_new


def test_watchdog_stops_the_robot_after_the_timeout(make_sim) -> None:
    sim = make_sim()
    drive(sim, 0.2, 0.0, 1.0)
    for _ in range(round(0.5 / sim.params.physics_step)):   # within the 0.5 s timeout: keeps going
        sim.step()
    assert sim.v == pytest.approx(0.2)
    for _ in range(round(0.5 / sim.params.physics_step)):   # then it brakes to a stop
        sim.step()
    assert sim.v == 0.0


def test_integrate_inverts_for_reverse_motion() -> None:
    start = Pose2D(1.0, 2.0, 0.3)
    there = integrate(start, 0.2, 0.4, 1.5)
    back = integrate(there, -0.2, -0.4, 1.5)
    assert (back.x, back.y, back.yaw) == pytest.approx((start.x, start.y, start.yaw), abs=1e-12)


def test_unknown_robot_model_is_rejected() -> None:
    with pytest.raises(ValueError, match="unknown model 'kobuki'"):
        robot_model("kobuki")
