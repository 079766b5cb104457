"""What a refined match says per direction (match_information.py): which returns face a direction,
the fit of those returns along a corridor, and the curvature of the refined peak.

A corridor's side walls say nothing about the position along it; a pillar in view does. These tests
pin down that the fit along the corridor uses the pillar and ignores the walls, and that without a
pillar it measures nothing (the pose then keeps the odometry prediction, tracking.tracked_pose).
"""

from __future__ import annotations

import numpy as np

from nav_stack.core.geometry import Pose2D
from nav_stack.core.slam import CorrelationGrid, scan_points
from nav_stack.core.slam.laser import JOIN_GAP, densify, to_map
from nav_stack.core.slam.match_information import along_axis, facing, peak_information
from navsuite_testing.slam.world import World

ALONG_X = np.array([1.0, 0.0])


def corridor(pillar: bool) -> World:
    """Two walls 2 m apart along x, far longer than the laser range, with a pillar 2 m ahead."""
    walls = np.array([(-20.0, -1.0, 20.0, -1.0), (-20.0, 1.0, 20.0, 1.0)])
    circles = np.array([(2.0, 0.5, 0.12)]) if pillar else np.zeros((0, 3))
    return World(walls, circles)


def fine_grid_and_hits(world: World, truth: Pose2D) -> tuple[CorrelationGrid, np.ndarray]:
    """A refinement grid of one noiseless scan at ``truth`` (joined returns, map frame) and the hits
    of a second scan from the same pose (robot frame)."""
    hits = scan_points(world.scan(truth), Pose2D(0.0, 0.0, 0.0), 3.5).hits
    reference = to_map(densify(hits, 0.01, JOIN_GAP), truth)
    return CorrelationGrid(reference, (truth.x, truth.y), 3.9, 0.02, 0.03), hits


def test_side_wall_returns_do_not_face_along_the_corridor_and_the_pillars_do() -> None:
    hits = scan_points(corridor(pillar=True).scan(Pose2D(0.0, 0.0, 0.0)), Pose2D(0.0, 0.0, 0.0), 3.5).hits
    facing_x = facing(hits, ALONG_X, JOIN_GAP)
    on_walls = np.abs(np.abs(hits[:, 1]) - 1.0) < 0.02
    assert not facing_x[on_walls].any()
    on_pillar = np.hypot(hits[:, 0] - 2.0, hits[:, 1] - 0.5) < 0.15
    assert on_pillar.sum() >= 3 and facing_x[on_pillar].sum() >= 3
    # they face across it, but for grazing returns too far apart to have a neighbour on the wall
    assert facing(hits, np.array([0.0, 1.0]), JOIN_GAP)[on_walls].mean() > 0.8


def test_the_pillar_fixes_the_position_along_the_corridor() -> None:
    truth = Pose2D(0.0, 0.0, 0.0)
    grid, hits = fine_grid_and_hits(corridor(pillar=True), truth)
    predicted = Pose2D(0.03, 0.0, 0.0)  # odometry ran 3 cm long
    fit = along_axis(grid, hits, truth, predicted, ALONG_X, 0.01, JOIN_GAP)
    assert abs(fit.offset + 0.03) < 0.005
    assert fit.information > 0.02**-2  # a few returns on the pillar: under 2 cm
    # the prediction (1 cm) moves back in proportion to the information of each
    weight = fit.information / (fit.information + 0.01**-2)
    assert np.isclose(fit.correction, weight * fit.offset) and fit.correction < -0.005


def test_without_a_pillar_nothing_is_measured_along_the_corridor() -> None:
    truth = Pose2D(0.0, 0.0, 0.0)
    grid, hits = fine_grid_and_hits(corridor(pillar=False), truth)
    fit = along_axis(grid, hits, truth, Pose2D(0.03, 0.0, 0.0), ALONG_X, 0.01, JOIN_GAP)
    assert fit.information == 0.0 and fit.correction == 0.0


def test_the_peak_is_sharper_across_the_corridor_than_along_it() -> None:
    """Across the corridor the walls pin the pose under 1 cm; along it only the ends of the
    reference's dotted walls curve the peak (which is why a link takes the peak's information only
    in the directions the coarse match fixed, tracking.link_information)."""
    truth = Pose2D(0.0, 0.0, 0.0)
    grid, hits = fine_grid_and_hits(corridor(pillar=False), truth)
    info = peak_information(grid, hits, truth, np.diag([0.2**2, 0.05**2, 0.01**2]), 0.00349)
    assert info[1, 1] > 100.0**2
    assert info[0, 0] < 0.5 * info[1, 1]
