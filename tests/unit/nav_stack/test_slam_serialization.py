"""Saving a SLAM session, continuing it and localizing on it (nav_stack/core/slam/serialization.py,
mapper.GridSlam.from_graph / restart_at, localization.GraphLocalizer), in the hexagon room."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from nav_stack.core.geometry import Pose2D
from nav_stack.core.slam import GraphFileError, GraphLocalizer, GridSlam, SlamParams, read_graph, write_graph
from nav_stack.core.slam.serialization import graph_paths
from navsuite_testing.slam.world import NoisyOdometry, hexagon_world, interpolate

START = Pose2D(-2.0, -0.5, 0.0)
FIRST_LEG = [START, Pose2D(-0.55, -0.5, 0.0), Pose2D(-0.55, 1.8, 0.0)]
SECOND_LEG = [Pose2D(-0.55, 1.8, 0.0), Pose2D(1.8, 1.6, 0.0), Pose2D(2.0, -0.5, 0.0)]
PARAMS = SlamParams(map_start_pose=(START.x, START.y, START.yaw))


def drive(slam: GridSlam, legs: list[Pose2D], seed: int, t0: float = 0.0) -> list[float]:
    """Feed scans along ``legs`` with drifting odometry (a fresh odom frame); return the pose errors (m)."""
    world, rng = hexagon_world(), np.random.default_rng(seed)
    odometry = NoisyOdometry(rng, translation_noise=0.05, rotation_noise=0.05, rotation_bias=0.05)
    errors = []
    for k, true_pose in enumerate(interpolate(legs, 0.1)):
        odom = odometry.update(true_pose)
        update = slam.process(world.scan(true_pose, noise_std=0.01, rng=rng), odom, t0 + 0.2 * k)
        errors.append(math.hypot(update.pose.x - true_pose.x, update.pose.y - true_pose.y))
    return errors


@pytest.fixture(scope="module")
def session() -> GridSlam:
    slam = GridSlam(PARAMS)
    drive(slam, FIRST_LEG, seed=3)
    return slam


def test_round_trip_keeps_the_map_bytes_poses_and_edges(session: GridSlam, tmp_path: Path) -> None:
    graph_file, data_file = write_graph(session.graph(), tmp_path / "room")
    assert (graph_file.name, data_file.name) == ("room.posegraph", "room.data")
    assert not list(tmp_path.glob(".*tmp*")), "temporary files were left behind"
    restored = GridSlam.from_graph(read_graph(tmp_path / "room"))
    before, spec = session.occupancy()
    after, spec_after = restored.occupancy()
    assert spec_after == spec and after.tobytes() == before.tobytes()
    np.testing.assert_array_equal(restored.poses, session.poses)
    assert len(restored.edges) == len(session.edges)
    for a, b in zip(restored.edges, session.edges, strict=True):
        assert (a.i, a.j, a.z, a.robust) == (b.i, b.j, b.z, b.robust)
        np.testing.assert_array_equal(a.information, b.information)
    assert restored.params == session.params and restored.map_to_odom == session.map_to_odom
    header = yaml.safe_load(graph_file.read_text())
    assert header["format"] == "navsuite-slam-posegraph" and header["version"] == 1
    assert header["nodes"] == len(session.poses) > 10


def test_a_restored_session_continues_where_it_is_told(session: GridSlam, tmp_path: Path) -> None:
    write_graph(session.graph(), tmp_path / "room")
    slam = GridSlam.from_graph(read_graph(tmp_path / "room"))
    saved_nodes = len(slam.poses)
    slam.restart_at(SECOND_LEG[0])  # the robot stands where the first session ended, new odom frame
    errors = drive(slam, SECOND_LEG, seed=4, t0=0.0)  # sim time may restart, too
    assert max(errors) <= 0.1, f"max error {max(errors):.3f} m"
    assert len(slam.poses) > saved_nodes + 10
    np.testing.assert_allclose(slam.poses[:saved_nodes], session.poses, atol=0.05)
    occupancy, _ = slam.occupancy()
    known_before = int((session.occupancy()[0] >= 0).sum())
    assert int((occupancy >= 0).sum()) > known_before  # the map grew into the new leg


def test_localization_tracks_without_changing_the_graph_or_the_map(session: GridSlam, tmp_path: Path) -> None:
    write_graph(session.graph(), tmp_path / "room")
    localizer = GraphLocalizer.from_graph(read_graph(tmp_path / "room"))
    before = localizer.occupancy()[0].tobytes()
    back = list(reversed(FIRST_LEG))
    localizer.restart_at(back[0])
    errors = drive(localizer, back, seed=5)
    assert max(errors) <= 0.1, f"max error {max(errors):.3f} m"
    assert localizer.localized_scans > 10
    assert len(localizer.poses) == len(session.poses) and len(localizer.edges) == len(session.edges)
    assert localizer.occupancy()[0].tobytes() == before


def test_resolution_must_match_the_saved_map(session: GridSlam) -> None:
    with pytest.raises(ValueError, match="resolution"):
        GridSlam.from_graph(session.graph(), SlamParams(resolution=0.1))


def _rewrite_header(base: Path, **changes: object) -> None:
    graph_file, _ = graph_paths(base)
    header = yaml.safe_load(graph_file.read_text())
    header.update(changes)
    graph_file.write_text(yaml.safe_dump(header))


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        (lambda base: graph_paths(base)[0].unlink(), r"room\.posegraph: cannot read"),
        (lambda base: graph_paths(base)[1].unlink(), r"room\.data: cannot read"),
        (lambda base: _rewrite_header(base, version=99), r"room\.posegraph: field 'version'"),
        (lambda base: _rewrite_header(base, nodes=3), r"room\.data: field 'poses'"),
        (lambda base: _rewrite_header(base, map_to_odom=[1.0]), r"room\.posegraph: field 'map_to_odom'"),
        (lambda base: graph_paths(base)[1].write_bytes(b"junk"), r"room\.posegraph: field 'data_sha256'"),
        (lambda base: graph_paths(base)[0].write_text("[unclosed"), r"room\.posegraph: not YAML"),
    ],
)
def test_a_broken_file_is_an_error_naming_the_file_and_field(
    session: GridSlam, tmp_path: Path, damage: object, message: str
) -> None:
    write_graph(session.graph(), tmp_path / "room")
    damage(tmp_path / "room")  # type: ignore[operator]
    with pytest.raises(GraphFileError, match=message):
        read_graph(tmp_path / "room")
