"""Odometry slip (the odometry integrates a scaled motion for a span of sim time) and topic loss (an
output that publishes nothing for a span of sim time): the windows, the checks, the simulator's use."""

from __future__ import annotations

import math

import pytest

from sim2d.core.disturbances import LOSABLE_TOPICS, OdometrySlip, TopicLoss
from sim2d.core.odometry import OdometryParams
from tests.unit.sim2d.conftest import drive

SECOND = 1_000_000_000


def test_a_slip_scales_the_increment_inside_its_window_only() -> None:
    slip = OdometrySlip()
    assert slip.apply(0, 1.0, 0.5, 0.1) == (1.0, 0.5, 0.1)
    slip.start(SECOND, 1.5, 2.0)
    assert slip.apply(SECOND - 1, 1.0, 0.0, 0.2) == (1.0, 0.0, 0.2)
    assert slip.apply(SECOND, 1.0, 0.0, 0.2) == pytest.approx((1.5, 0.0, 0.3))
    assert slip.apply(3 * SECOND, 1.0, 0.0, 0.2) == (1.0, 0.0, 0.2)
    slip.start(4 * SECOND, 2.0, 10.0)
    slip.start(5 * SECOND, 2.0, 0.0)      # <= 0 ends a running slip
    assert not slip.active(5 * SECOND)


@pytest.mark.parametrize(("scale", "duration"), [(-0.1, 1.0), (math.nan, 1.0), (1.0, math.inf)])
def test_a_slip_refuses_a_negative_or_non_finite_value(scale: float, duration: float) -> None:
    with pytest.raises(ValueError, match="odometry slip"):
        OdometrySlip().start(0, scale, duration)


def test_a_topic_loss_silences_one_topic_for_its_window() -> None:
    loss = TopicLoss()
    loss.start("scan", SECOND, 0.5)
    assert not loss.lost("scan", SECOND - 1)
    assert loss.lost("scan", SECOND) and not loss.lost("odom", SECOND)
    assert not loss.lost("scan", SECOND + SECOND // 2)
    loss.start("odom", 0, 1.0)
    loss.start("odom", 0, 0.0)
    assert not loss.lost("odom", 0)


def test_a_topic_loss_names_the_topics_it_knows() -> None:
    assert set(LOSABLE_TOPICS) == {"scan", "odom", "tf", "battery_state"}
    with pytest.raises(ValueError, match="unknown topic 'clock'"):
        TopicLoss().start("clock", 0, 1.0)


def test_odometry_under_slip_reports_the_scaled_distance_and_the_truth_does_not_change(make_sim) -> None:
    ideal = OdometryParams(ideal=True)
    plain, slipping = make_sim(odometry=ideal), make_sim(odometry=ideal)
    slipping.slip_odometry(1.5, 10.0)
    for sim in (plain, slipping):
        drive(sim, 0.2, 0.0, 2.0)
    assert slipping.pose == plain.pose                                  # the world does not notice
    assert plain.odometry.pose.x > 0.2
    assert slipping.odometry.pose.x == pytest.approx(1.5 * plain.odometry.pose.x, rel=1e-9)


def test_odometry_is_exact_again_after_the_slip_ends(make_sim) -> None:
    sim = make_sim(odometry=OdometryParams(ideal=True))
    sim.slip_odometry(0.0, 1.0)                                          # wheels turn, odometry sees nothing
    drive(sim, 0.2, 0.0, 1.0)
    frozen = sim.odometry.pose.x
    assert frozen == 0.0 and sim.pose.x > -2.0
    start_truth = sim.pose.x
    drive(sim, 0.2, 0.0, 1.0)
    assert sim.odometry.pose.x - frozen == pytest.approx(sim.pose.x - start_truth, rel=1e-9)
