"""amcl's message layouts: the (x, y, yaw) covariance round-trips through Nav2's 6×6 placement, and
the localization health becomes one /diagnostics status."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.msg", reason="nav2_msgs is not built (run the interface build)")

from diagnostic_msgs.msg import DiagnosticStatus

from nav_stack.core.localization.health import HealthMonitor, HealthParams, HealthSample
from nav_stack.ros.localization.amcl_messages import (
    LOCALIZATION_STATUS,
    covariance_3x3,
    estimate_msg,
    health_msg,
    particle_cloud_msg,
    time_msg,
)


def test_estimate_places_the_covariance_where_nav2_clients_read_it() -> None:
    cov = np.array([[0.25, 0.01, 0.0], [0.02, 0.16, 0.0], [0.0, 0.0, 0.07]])
    msg = estimate_msg(1.0, -2.0, math.pi / 2, cov, "map", 12.5)
    assert msg.header.frame_id == "map"
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (12, 500_000_000)
    assert (msg.pose.covariance[0], msg.pose.covariance[7], msg.pose.covariance[35]) == (0.25, 0.16, 0.07)
    assert (msg.pose.covariance[1], msg.pose.covariance[6]) == (0.01, 0.02)
    np.testing.assert_array_equal(covariance_3x3(msg.pose.covariance), cov)
    assert msg.pose.pose.orientation.z == pytest.approx(math.sin(math.pi / 4))


def test_particle_cloud_carries_every_particle_and_weight() -> None:
    particles = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, math.pi]])
    cloud = particle_cloud_msg(particles, np.array([0.25, 0.75]), "map", time_msg(3.0))
    assert [p.weight for p in cloud.particles] == [0.25, 0.75]
    assert cloud.particles[1].pose.position.y == 2.0 and cloud.header.stamp.sec == 3


def test_health_status_is_ok_then_warn_with_the_cause_and_the_numbers() -> None:
    monitor = HealthMonitor(HealthParams(bad_updates_to_degrade=1))
    ok = health_msg(monitor, 4.0).status[0]
    assert (ok.name, ok.level, ok.message) == (LOCALIZATION_STATUS, DiagnosticStatus.OK, "localized")
    assert ok.values == []  # no numbers before the first filter update
    monitor.update(HealthSample(60, 9, 9, 3.5, 0.12, 0.05))
    msg = health_msg(monitor, 5.5)
    warn = msg.status[0]
    assert warn.level == DiagnosticStatus.WARN and msg.header.stamp.sec == 5
    assert warn.message == "few beams on walls: 9 of 60 beams returned within 3.5 m (< 20 %)"
    assert {kv.key: kv.value for kv in warn.values} == {
        "valid beams": "9 of 60 within 3.5 m", "matched ratio": "1.00", "position std (m)": "0.120",
        "yaw std (rad)": "0.050"}
