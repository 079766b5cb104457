"""Grid SLAM loop closure: candidate chains, and a ring corridor larger than the lidar range."""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.geometry import Pose2D
from nav_stack.core.slam import GridSlam, SlamParams
from nav_stack.core.slam.loop_closure import candidate_chains
from navsuite_testing.slam.world import NoisyOdometry, interpolate, ring_world

START = Pose2D(-4.25, -4.25, 0.0)
LAP = [
    START,
    Pose2D(4.25, -4.25, 0.0),
    Pose2D(4.25, 4.25, 0.0),
    Pose2D(-4.25, 4.25, 0.0),
    START,
    Pose2D(-1.5, -4.25, 0.0),
]


def test_candidate_chains_skip_linked_scans_and_short_runs() -> None:
    # A chain of 30 nodes walking out along x and back; node 29 is near nodes 0..3 and 25..28.
    xs = np.concatenate((np.arange(15) * 0.2, (14 - np.arange(15)) * 0.2))
    poses = np.column_stack((xs, np.where(np.arange(30) < 15, 0.0, 0.1), np.zeros(30)))
    adjacency = [[k - 1] * (k > 0) + [k + 1] * (k < 29) for k in range(30)]
    chains = candidate_chains(poses, adjacency, 29, max_distance=0.7, min_chain=3)
    assert chains == [[0, 1, 2, 3]]  # 25..28 are linked to 29 through near nodes: excluded
    assert candidate_chains(poses, adjacency, 29, max_distance=0.7, min_chain=5) == []
    adjacency[29].append(2)  # after a closure with node 2 the old chain is linked, so no repeat
    adjacency[2].append(29)
    assert candidate_chains(poses, adjacency, 29, max_distance=0.7, min_chain=3) == []


def test_loop_closure_reduces_the_error_after_a_lap() -> None:
    world = ring_world()
    rng = np.random.default_rng(1)
    odometry = NoisyOdometry(rng, translation_noise=0.08, rotation_noise=0.05, rotation_bias=0.05)
    slam = GridSlam(SlamParams(map_start_pose=(START.x, START.y, START.yaw)))
    error_before = error_after = math.nan
    closed_at = None
    for k, true_pose in enumerate(interpolate(LAP, 0.2)):
        update = slam.process(
            world.scan(true_pose, noise_std=0.01, rng=rng), odometry.update(true_pose), 0.2 * k
        )
        error = math.hypot(update.pose.x - true_pose.x, update.pose.y - true_pose.y)
        if closed_at is None and update.loop_closed:
            closed_at = k
        elif closed_at is None:
            error_before = error  # scan matching alone, just before the closure
        elif k == closed_at + 3:
            error_after = error
            break
    assert closed_at is not None and slam.loop_closures >= 1
    assert error_before > 0.04  # scan matching alone drifts along the featureless corridors
    assert error_after < 0.5 * error_before
    assert tuple(slam.poses[0]) == (START.x, START.y, START.yaw)  # the anchor (map frame) never moves
