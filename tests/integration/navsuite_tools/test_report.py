"""Run reports: the numbers (localization error, state segments) and the rendered PNG."""

from __future__ import annotations

import numpy as np
import pytest
from geometry_msgs.msg import Twist
from matplotlib.image import imread

from navsuite_tools.bag.writer import BagWriter
from navsuite_tools.report import ReportParams, write_report
from navsuite_tools.report.analysis import (
    Transition,
    distinct_points,
    localization_error,
    make_trajectory,
    state_segments,
)
from navsuite_tools.report.extract import load_run
from navsuite_tools.report.render import AMCL_COLOR, COLLISION_COLOR, TRUTH_COLOR
from ros_tools.geometry import yaw_from_quaternion
from tests.helpers.bag_synthetic import DURATION, T0, TRANSITIONS, write_synthetic_run
from tests.helpers.report_pixels import content_fraction, distinct_colors, load_rgb, pixels_near

SMALL = ReportParams(width_px=1000, height_px=600, dpi=80)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return write_synthetic_run(tmp_path_factory.mktemp("report") / "run.mcap")


# ---------------------------------------------------------------- analysis
def test_localization_error_interpolates_truth_at_estimate_stamps():
    t = np.linspace(0.0, 10.0, 101)
    truth = make_trajectory(t, np.c_[t, 2 * t], np.zeros_like(t))
    stamps = np.array([0.55, 3.33, 9.99, 12.0])  # the last is after the truth ends: dropped
    estimate = make_trajectory(stamps, np.c_[stamps + 0.3, 2 * stamps + 0.4], np.zeros(4))
    times, error = localization_error(truth, estimate)
    assert times == pytest.approx(stamps[:3])
    assert error == pytest.approx([0.5, 0.5, 0.5])


def test_localization_error_is_empty_without_overlap():
    truth = make_trajectory([0.0, 1.0], [[0, 0], [1, 0]], [0, 0])
    estimate = make_trajectory([5.0], [[0, 0]], [0])
    assert localization_error(truth, estimate)[0].size == 0


def test_state_segments_run_until_the_next_transition_or_the_end():
    transitions = [Transition(t, "Sm", src, dst, tag, "") for t, src, dst, tag in TRANSITIONS]
    segments = state_segments(list(reversed(transitions)), end=20.0)
    assert [(s.state, s.start, s.end, s.tag) for s in segments] == [
        ("StAcquireSensors", 0.0, 2.0, "SUCCESS"),
        ("StNavigateToWaypoint", 2.0, 12.0, "SUCCESS"),
        ("StRecovery", 12.0, 15.0, "ABORT"),
        ("StNavigateToWaypoint", 15.0, 20.0, "SUCCESS"),
    ]


def test_yaw_and_goal_deduplication():
    assert yaw_from_quaternion(0.0, 0.0, np.sin(0.6), np.cos(0.6)) == pytest.approx(1.2)
    ends = distinct_points(np.array([[1.0, 1.0], [1.01, 1.0], [2.0, 1.0], [1.0, 1.02]]), 0.05)
    assert ends.tolist() == [[1.0, 1.0], [2.0, 1.0]]


# ---------------------------------------------------------------- extraction
def test_run_data_holds_every_series(run):
    data = load_run(run.path)
    assert data.last_map is not None and data.map_count == 1
    assert data.last_map.extent == pytest.approx((-2.0, 2.0, -1.5, 1.5))
    assert data.last_map.data[0, 0] == 100 and data.last_map.data[10, 75] == -1
    assert len(data.truth) == run.counts["/ground_truth"] and len(data.amcl) == run.counts["/amcl_pose"]
    assert len(data.plans) == run.counts["/plan"] and data.goals.shape == (2, 3)
    assert data.collisions[:, 1:].tolist() == [[-1.0, -0.5]]
    assert [tr.target for tr in data.transitions] == [tr[2] for tr in TRANSITIONS]
    assert {tr.machine for tr in data.transitions} == {"SmTest"}
    assert data.time_origin() == pytest.approx(T0)
    assert data.duration == pytest.approx(DURATION)


# ---------------------------------------------------------------- rendering
def test_report_png_has_the_size_and_shows_the_run(run, tmp_path):
    out = write_report(run.path, tmp_path / "out" / "report.png", SMALL)
    assert out.is_file() and out.is_absolute()
    rgb = load_rgb(out)
    assert rgb.shape[:2] == (SMALL.height_px, SMALL.width_px)
    assert distinct_colors(rgb) > 50  # many distinct colours
    _, counts = np.unique(rgb.reshape(-1, 3), axis=0, return_counts=True)
    assert counts.max() / counts.sum() < 0.9  # not one colour
    assert content_fraction(rgb) > 0.04  # not mostly blank: a bare report has about 0.02
    dark = (rgb < 40).all(axis=2).mean()
    assert dark > 0.01  # walls and the pillar of the occupancy grid
    assert pixels_near(rgb, TRUTH_COLOR) > 300  # ground-truth trajectory
    assert pixels_near(rgb, AMCL_COLOR) > 100  # AMCL trajectory and error curve
    assert pixels_near(rgb, COLLISION_COLOR) > 20  # collision marker and timeline line


def test_report_without_ground_truth_has_no_trajectory_pixels(tmp_path):
    path = tmp_path / "bare.mcap"
    with BagWriter(path) as writer:
        writer.write_message("/cmd_vel", Twist(), 1_000_000_000)
    out = write_report(path, tmp_path / "bare.png", SMALL)
    rgb = load_rgb(out)
    assert rgb.shape[:2] == (SMALL.height_px, SMALL.width_px)
    assert pixels_near(rgb, TRUTH_COLOR) == 0
    assert content_fraction(rgb) < 0.04


def test_report_params_are_checked():
    with pytest.raises(ValueError, match="map_choice"):
        ReportParams(map_choice="middle")
    with pytest.raises(ValueError, match="too small"):
        ReportParams(width_px=10)


def test_report_cli_prints_the_png_path(run, tmp_path, capsys):
    from navsuite_tools.bag.main import main

    out = tmp_path / "cli.png"
    assert main(["report", str(run.path), "-o", str(out), "--width", "800", "--height", "500"]) == 0
    assert capsys.readouterr().out.strip() == str(out.resolve())
    assert imread(out).shape[:2] == (500, 800)
