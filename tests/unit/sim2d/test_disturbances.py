"""Injected faults: a lidar dropout (every beam +inf for a span of sim time) and an obstacle dropped
into the running world (seen by the lidar, blocking the robot, refused on top of the robot)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim2d.core.disturbances import DroppedObstacle, LidarDropout
from sim2d.core.robot import WAFFLE, Pose2D
from tests.unit.sim2d.conftest import drive

SECOND = 1_000_000_000


def test_a_dropout_window_covers_its_duration_of_sim_time_and_no_more() -> None:
    dropout = LidarDropout()
    assert not dropout.active(0)
    dropout.start(2 * SECOND, 3.0)
    assert not dropout.active(2 * SECOND - 1)
    assert dropout.active(2 * SECOND) and dropout.active(5 * SECOND - 1)
    assert not dropout.active(5 * SECOND)
    assert dropout.remaining(4 * SECOND) == pytest.approx(1.0)
    assert dropout.remaining(6 * SECOND) == 0.0


def test_a_new_dropout_replaces_the_running_one_and_zero_ends_it() -> None:
    dropout = LidarDropout()
    dropout.start(0, 10.0)
    dropout.start(SECOND, 0.0)
    assert not dropout.active(SECOND)
    with pytest.raises(ValueError, match="finite"):
        dropout.start(0, math.inf)


def test_scans_read_no_return_during_the_dropout_then_the_walls_again(make_sim) -> None:
    sim = make_sim()
    assert np.isfinite(sim.scan()).any()
    sim.drop_lidar(0.5)
    assert np.all(sim.scan() == np.inf)
    drive(sim, 0.0, 0.0, 0.5)
    assert np.isfinite(sim.scan()).any()


def test_a_dropout_leaves_the_noise_stream_where_it_would_be(make_sim) -> None:
    plain, faulty = make_sim(seed=3), make_sim(seed=3)
    faulty.drop_lidar(0.1)
    for sim in (plain, faulty):
        sim.scan()
        drive(sim, 0.0, 0.0, 0.1)
    np.testing.assert_array_equal(plain.scan(), faulty.scan())


def test_a_dropped_obstacle_is_seen_by_the_lidar(make_sim) -> None:
    sim = make_sim()                                    # the waffle at (-2, -0.5) facing +x
    ahead = float(sim.scan()[0])
    sim.drop_obstacle(DroppedObstacle(-1.5, -0.5 + sim.robot.scan_offset[1], 0.1))
    scan_x = sim.scan_pose().x
    assert float(sim.scan()[0]) == pytest.approx(-1.5 - 0.1 - scan_x, abs=0.05)
    assert float(sim.scan()[0]) < ahead


def test_a_dropped_obstacle_stops_the_robot_and_counts_one_collision(make_sim) -> None:
    sim = make_sim()
    assert sim.drop_obstacle(DroppedObstacle(-1.3, -0.5, 0.15))
    drive(sim, 0.26, 0.0, 6.0)
    front = sim.pose.x + WAFFLE.footprint_offset_x + WAFFLE.footprint_length / 2
    assert front == pytest.approx(-1.3 - 0.15, abs=2e-3)
    assert sim.collision_count == 1 and sim.dropped == [DroppedObstacle(-1.3, -0.5, 0.15)]


def test_an_obstacle_on_the_robot_is_refused_and_changes_nothing(make_sim) -> None:
    sim = make_sim()
    before = sim.scan()
    assert not sim.drop_obstacle(DroppedObstacle(-2.0, -0.4, 0.2))
    assert sim.dropped == [] and len(sim.lidar.geometry.circles) == len(sim.world.geometry.circles)
    np.testing.assert_allclose(sim.scan(), before, atol=0.1)
    drive(sim, 0.2, 0.0, 1.0)
    assert sim.collision_count == 0


def test_reset_keeps_dropped_obstacles(make_sim) -> None:
    sim = make_sim(Pose2D(-2.0, -1.1, 0.0))
    sim.drop_obstacle(DroppedObstacle(0.0, -2.0, 0.2))
    sim.reset()
    assert len(sim.lidar.geometry.circles) == len(sim.world.geometry.circles) + 1


@pytest.mark.parametrize("fields", [(0.0, 0.0, 0.0), (0.0, 0.0, -1.0), (math.nan, 0.0, 0.2)])
def test_a_bad_obstacle_is_refused_naming_the_value(fields: tuple[float, float, float]) -> None:
    with pytest.raises(ValueError, match="obstacle"):
        DroppedObstacle(*fields)
