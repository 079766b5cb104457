"""Grid SLAM in a deliberately symmetric world: a look-alike loop closure must not bend the map.

The world is a straight corridor lined with identical pillars every 0.9 m, longer than the lidar
reach, so a scan fits the scans of the same stretch equally well at every multiple of 0.9 m. The
robot drives 7.2 m out and back while odometry drifts 0.6 m; scan matching is off so the estimate
carries that drift into the loop search. Back at the start, the nearest look-alike (0.3 m from
the estimate) then beats the true alignment (0.6 m away) under the matcher's distance penalty:
the world offers a false closure. A closure check on the responses alone accepts a constraint
about one period wrong; the verified closure sees two near-equal peaks and rejects the match.

A false edge that does get in is the pose graph's problem: the last test gives it two correct
closures to disagree with and checks that the Cauchy kernel leaves the poses where they belong.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from nav_stack.core.geometry import Pose2D
from nav_stack.core.slam import Edge, GridSlam, SlamParams, between, optimize
from navsuite_testing.slam.world import World, interpolate

PERIOD = 0.9  # m between identical pillars
DRIFT = 0.6  # m of odometry drift (+x) accumulated over the whole drive
START = Pose2D(0.0, 0.0, 0.0)
DRIVE = [START, Pose2D(7.2, 0.0, 0.0), Pose2D(7.2, 0.0, math.pi), START]


def periodic_corridor() -> World:
    """A 1.5 m wide corridor from x = -6 to 14 m with pillars (r 0.1 m) on both walls every PERIOD."""
    walls = np.array([(-6.0, -0.75, 14.0, -0.75), (-6.0, 0.75, 14.0, 0.75)])
    xs = np.arange(-6.0, 14.0, PERIOD) + 0.45
    pillars = np.array([(x, y, 0.1) for x in xs for y in (-0.6, 0.6)])
    return World(walls, pillars)


def drive(params: SlamParams) -> tuple[GridSlam, list[Pose2D]]:
    """Run the out-and-back drive; returns the SLAM and the true pose of every pose-graph node."""
    world = periodic_corridor()
    rng = np.random.default_rng(7)
    path = interpolate(DRIVE, 0.1, turn_step=0.1)
    steps = [math.hypot(b.x - a.x, b.y - a.y) for a, b in itertools.pairwise(path)]
    travelled = np.concatenate(([0.0], np.cumsum(steps)))
    slam = GridSlam(params)
    truth: list[Pose2D] = []
    for k, (true_pose, dist) in enumerate(zip(path, travelled, strict=True)):
        odom = Pose2D(true_pose.x + DRIFT * dist / travelled[-1], true_pose.y, true_pose.yaw)
        if slam.process(world.scan(true_pose, noise_std=0.01, rng=rng), odom, 0.1 * k).processed:
            truth.append(true_pose)
    return slam, truth


def test_the_symmetric_world_offers_a_false_closure_that_a_response_check_accepts() -> None:
    slam, truth = drive(SlamParams(use_scan_matching=False, loop_match_maximum_stddev=10.0))
    loops = [e for e in slam.edges if e.robust]
    assert loops
    wrong = [abs(e.z[0] - between(truth[e.i], truth[e.j]).x) for e in loops]  # along the corridor
    assert max(wrong) > 0.5 * PERIOD


def test_a_false_closure_in_a_symmetric_world_is_rejected_and_the_map_stays_as_measured() -> None:
    reference, _ = drive(SlamParams(use_scan_matching=False, do_loop_closing=False))
    slam, _ = drive(SlamParams(use_scan_matching=False))
    assert slam.loop_closures == 0
    assert slam.loop_closures_rejected >= 1
    np.testing.assert_array_equal(slam.poses, reference.poses)
    occupancy, spec = slam.occupancy()
    expected, expected_spec = reference.occupancy()
    assert spec == expected_spec
    np.testing.assert_array_equal(occupancy, expected)


def test_the_robust_kernel_outvotes_a_false_loop_edge_that_contradicts_the_graph() -> None:
    truth = np.column_stack((0.2 * np.arange(20), np.zeros(20), np.zeros(20)))
    info = np.diag([400.0, 400.0, 2500.0])
    chain = [Edge(k, k + 1, (0.2, 0.0, 0.0), info) for k in range(19)]

    def loop(i: int, j: int, offset: float, robust: bool) -> Edge:
        return Edge(i, j, (0.2 * (j - i) + offset, 0.0, 0.0), info, robust=robust)

    start = truth + np.column_stack((np.linspace(0.0, 0.3, 20), np.zeros(20), np.zeros(20)))  # drifted
    errors = {}
    for robust in (False, True):
        edges = [*chain, loop(0, 19, 0.0, robust), loop(4, 15, 0.0, robust), loop(2, 17, 0.6, robust)]
        solved = optimize(start, edges, max_iterations=20)
        errors[robust] = float(np.abs(solved[:, 0] - truth[:, 0]).max())
    assert errors[False] > 0.05  # least squares splits the difference with the false edge
    assert errors[True] < 0.02
