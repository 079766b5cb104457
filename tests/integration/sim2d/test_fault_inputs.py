"""sim2d's fault topics over rclpy: odometry slip (/odom runs ahead of the truth while it lasts) and a
topic loss (/scan falls silent for its sim time, then comes back; other outputs go on)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

import itertools

from diagnostic_msgs.msg import KeyValue
from std_msgs.msg import Float64MultiArray

from tests.integration.sim2d.test_sim_node import Rig, _drive, _rig, _sim_time

pytestmark = pytest.mark.ros


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    yield from _rig(ros_context, **{"odometry.ideal": True})


def _odom_x(rig: Rig) -> float:
    return float(rig.last("/odom").pose.pose.position.x)


def test_odometry_slip_scales_the_reported_motion_while_the_truth_does_not(rig: Rig) -> None:
    rig.wait_sim(0.2)
    rig.send("/sim2d/odometry_slip", Float64MultiArray(data=[2.0, 60.0]))
    rig.spin_until(lambda: rig.sim.sim.slip.active(rig.sim.sim.time_ns), "the slip to start")
    truth_start = rig.truth()[0]
    _drive(rig, 0.2, 0.0, lambda: rig.truth()[0] - truth_start > 0.3, "0.3 m of true motion")
    rig.wait_sim(0.3)                                   # stopped: the last /odom is at rest
    travelled = rig.truth()[0] - truth_start
    assert _odom_x(rig) == pytest.approx(2.0 * travelled, abs=0.02)


def test_a_bad_slip_message_is_refused_and_the_odometry_stays_true(rig: Rig) -> None:
    rig.wait_sim(0.2)
    rig.send("/sim2d/odometry_slip", Float64MultiArray(data=[-1.0, 5.0]))
    rig.send("/sim2d/topic_loss", KeyValue(key="clock", value="5"))
    truth_start = rig.truth()[0]
    _drive(rig, 0.2, 0.0, lambda: rig.truth()[0] - truth_start > 0.2, "0.2 m of true motion")
    rig.wait_sim(0.3)
    assert _odom_x(rig) == pytest.approx(rig.truth()[0] - truth_start, abs=0.01)
    assert not rig.sim.sim.slip.active(rig.sim.sim.time_ns)


def test_a_topic_loss_silences_the_scan_for_its_sim_time_and_the_odometry_goes_on(rig: Rig) -> None:
    rig.wait_sim(0.5)
    rig.send("/sim2d/topic_loss", KeyValue(key="/scan", value="1.0"))
    rig.spin_until(lambda: rig.sim.sim.topic_loss.lost("scan", rig.sim.sim.time_ns), "the loss to start")
    rig.wait_sim(2.0)
    stamps = sorted(_sim_time(m.header.stamp) for m in rig.received["/scan"])
    gaps = [later - earlier for earlier, later in itertools.pairwise(stamps)]
    assert max(gaps) == pytest.approx(1.2, abs=0.21)   # 5 Hz scans: 1 s lost makes a 1.0-1.2 s gap
    odom = sorted(_sim_time(m.header.stamp) for m in rig.received["/odom"])
    assert max(later - earlier for earlier, later in itertools.pairwise(odom)) < 0.05
