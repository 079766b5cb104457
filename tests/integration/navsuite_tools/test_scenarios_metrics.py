"""The farm's measured criteria from a recording: the smallest of sim2d's /sim2d/clearance values,
None when the run did not record it (the min_clearance criterion then fails as "not measured")."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("nav_msgs.msg")

from nav_msgs.msg import Odometry
from std_msgs.msg import Float64, Header

from navsuite_tools.bag.writer import BagWriter
from navsuite_tools.scenarios.metrics import measure, min_clearance


def _write(path: Path, clearances: list[float]) -> None:
    with BagWriter(path) as writer:
        for k, value in enumerate(clearances):
            t_ns = 100_000_000_000 + k * 33_000_000
            odom = Odometry(header=Header(frame_id="map"), child_frame_id="base_footprint")
            odom.header.stamp.sec, odom.header.stamp.nanosec = divmod(t_ns, 1_000_000_000)
            writer.write_message("/ground_truth", odom, t_ns)
            writer.write_message("/sim2d/clearance", Float64(data=value), t_ns)
            writer.write_message("/sim2d/real_time_factor", Float64(data=0.01), t_ns)  # not a clearance


def test_the_smallest_recorded_clearance_is_the_run_s(tmp_path: Path) -> None:
    mcap = tmp_path / "run.mcap"
    _write(mcap, [0.8, 0.31, 0.072, 0.0725, 0.4])
    metrics = measure(mcap)
    assert metrics.min_clearance == pytest.approx(0.072)
    assert metrics.collisions == 0 and metrics.sim_span == pytest.approx(4 * 0.033)


def test_a_recording_without_the_clearance_topic_measures_none(tmp_path: Path) -> None:
    mcap = tmp_path / "run.mcap"
    with BagWriter(mcap) as writer:
        writer.write_message("/sim2d/real_time_factor", Float64(data=3.0), 1)
    assert min_clearance(mcap) is None
