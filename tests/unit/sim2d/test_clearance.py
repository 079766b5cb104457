"""Ground-truth clearance (sim2d.core.clearance) against distances worked out by hand.

The waffle's footprint at the origin, yaw 0: x in [-0.197, 0.069], y in [-0.133, 0.133] (0.266 m box
centred 0.064 m behind base_footprint). Each case puts one obstacle where the nearest pair of points
is obvious: face to face, corner to corner, an obstacle's corner to the footprint's edge, a turned
robot, a round robot, a crossing, the cull's fallback; then a simulator with a dock and a dropped box.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from sim2d.core.clearance import (
    CULL_RANGE,
    footprint_clearance,
    placed_footprint,
    robot_clearance,
    simulator_clearance,
)
from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.geometry import StaticGeometry
from sim2d.core.robot import TB4, WAFFLE, Pose2D
from sim2d.core.world import parse_world
from tests.unit.sim2d.conftest import room_with_docks, sim_in

FRONT, BACK, SIDE = 0.069, -0.197, 0.133  # the waffle's footprint at the origin (m)
ORIGIN = Pose2D(0.0, 0.0, 0.0)
WEDGE = np.array([[0.0, 0.333], [0.2, 0.6], [-0.2, 0.6]])  # tip 0.2 m above the left side (y = 0.133)


def circles(*rows: tuple[float, float, float]) -> StaticGeometry:
    return StaticGeometry(circles=np.array(rows, dtype=np.float64).reshape(-1, 3))


def boxes(*rows: tuple[float, float, float, float]) -> StaticGeometry:
    return StaticGeometry(boxes=np.array(rows, dtype=np.float64).reshape(-1, 4))


def test_the_footprint_is_placed_at_the_pose() -> None:
    assert placed_footprint(WAFFLE, ORIGIN) == pytest.approx(
        np.array([[BACK, -SIDE], [FRONT, -SIDE], [FRONT, SIDE], [BACK, SIDE]]))
    turned = placed_footprint(WAFFLE, Pose2D(1.0, 2.0, math.pi / 2))  # the front now faces +y
    assert turned == pytest.approx(np.array([[1.133, 1.803], [1.133, 2.069], [0.867, 2.069], [0.867, 1.803]]))


@pytest.mark.parametrize(("geometry", "expected"), [
    (circles((1.0, 0.0, 0.2)), 1.0 - 0.2 - FRONT),                      # a drum ahead: face to face
    (circles((FRONT + 0.3, SIDE + 0.4, 0.1)), 0.5 - 0.1),                # a drum off the front-left corner
    (circles((-1.0, 0.0, 0.3)), 1.0 - 0.3 + BACK),                       # behind
    (boxes((0.5, -1.0, 0.6, 1.0)), 0.5 - FRONT),                         # a wall across the path
    (boxes((FRONT + 0.3, SIDE + 0.4, 2.0, 2.0)), 0.5),                   # corner to corner (3-4-5)
    (StaticGeometry(polygons=(WEDGE,)), 0.2),                            # the wedge's tip to our side
], ids=["drum-ahead", "drum-corner", "drum-behind", "wall", "box-corner", "wedge-to-side"])
def test_the_clearance_of_the_waffle_at_the_origin(geometry: StaticGeometry, expected: float) -> None:
    assert robot_clearance(WAFFLE, ORIGIN, geometry) == pytest.approx(expected, abs=1e-9)


def test_the_clearance_turns_with_the_robot_and_follows_a_round_body() -> None:
    drum_north = circles((0.0, 1.0, 0.2))
    facing_north = Pose2D(0.0, 0.0, math.pi / 2)
    assert robot_clearance(WAFFLE, facing_north, drum_north) == pytest.approx(1.0 - 0.2 - FRONT)
    assert robot_clearance(WAFFLE, ORIGIN, drum_north) == pytest.approx(1.0 - 0.2 - SIDE)
    # TB4: a 16-gon around the 0.171 m circle with an edge facing +x, so straight ahead it is the radius
    drum_ahead = circles((1.0, 0.0, 0.2))
    assert robot_clearance(TB4, ORIGIN, drum_ahead) == pytest.approx(1.0 - 0.2 - 0.171)
    # ... at 22.5 degrees the middle of the next edge, at 11.25 degrees a corner 0.171 / cos(pi/16) out
    drum_at_edge = circles((math.cos(math.pi / 8), math.sin(math.pi / 8), 0.2))
    assert robot_clearance(TB4, ORIGIN, drum_at_edge) == pytest.approx(1.0 - 0.2 - 0.171)
    drum_at_corner = circles((math.cos(math.pi / 16), math.sin(math.pi / 16), 0.2))
    corner = 0.171 / math.cos(math.pi / 16)
    assert robot_clearance(TB4, ORIGIN, drum_at_corner) == pytest.approx(1.0 - 0.2 - corner)


def test_touching_crossing_or_containing_reads_zero() -> None:
    assert robot_clearance(WAFFLE, ORIGIN, circles((FRONT + 0.1, 0.0, 0.1))) == pytest.approx(0.0)  # touching
    assert robot_clearance(WAFFLE, ORIGIN, circles((0.0, 0.0, 0.05))) == 0.0  # a drum inside the body
    assert robot_clearance(WAFFLE, ORIGIN, boxes((0.0, -1.0, 0.01, 1.0))) == 0.0  # a thin wall through it
    assert robot_clearance(WAFFLE, ORIGIN, boxes((-0.05, -0.05, 0.05, 0.05))) == 0.0  # a box inside it


def test_far_obstacles_are_measured_when_nothing_is_within_the_cull_and_no_obstacle_is_inf() -> None:
    far = CULL_RANGE + 2.0
    geometry = StaticGeometry(circles=np.array([[far, 0.0, 0.5]]),
                              boxes=np.array([[-far - 1.0, -1.0, -far, 1.0]]))
    assert robot_clearance(WAFFLE, ORIGIN, geometry) == pytest.approx(far - 0.5 - FRONT)
    assert footprint_clearance(placed_footprint(WAFFLE, ORIGIN), StaticGeometry()) == math.inf
    # a near obstacle and a nearer far one cannot happen: the nearest is always within the cull's answer
    near_and_far = StaticGeometry(circles=np.array([[0.9 + FRONT + 0.05, 0.0, 0.05], [far, 0.0, 0.5]]))
    assert robot_clearance(WAFFLE, ORIGIN, near_and_far) == pytest.approx(0.9)


def test_a_map_world_is_measured_by_its_boundary_segments() -> None:
    # A map world's obstacles are boxes of occupied cells; its lidar sees only their outer boundary,
    # given as segments: the clearance is measured against those.
    boundary = np.array([[1.0, -1.0, 1.0, 1.0], [1.0, 1.0, 2.0, 1.0]])
    geometry = StaticGeometry(boxes=np.array([[1.0, -1.0, 2.0, 1.0]]), segments=boundary)
    assert robot_clearance(WAFFLE, ORIGIN, geometry) == pytest.approx(1.0 - FRONT)


def test_the_simulator_s_clearance_counts_dropped_obstacles_and_dock_bodies() -> None:
    ring = {"type": "ring", "vertices": [[-2, -2], [2, -2], [2, 2], [-2, 2]], "thickness": 0.1}
    room = parse_world({"name": "room", "obstacles": [ring]}, Path("room.yaml"))
    sim = sim_in(room, ORIGIN)
    assert simulator_clearance(sim) == pytest.approx(2.0 + BACK)  # the wall behind is nearest
    assert sim.drop_obstacle(DroppedObstacle(0.5, 0.0, 0.1))
    assert simulator_clearance(sim) == pytest.approx(0.5 - 0.1 - FRONT)
    docked_room = room_with_docks({"id": "a", "type": "create3_dock", "pose": [0.0, 0.0, 0.0]})
    # TB4 0.5 m before the contact pose: its round front (0.171 m) to the dock body's near face
    near_face = float(docked_room.docks[0].body(TB4)[:, 0].min())
    assert simulator_clearance(sim_in(docked_room, Pose2D(-0.5, 0.0, 0.0), TB4)) == pytest.approx(
        near_face - (-0.5 + 0.171))
    assert simulator_clearance(sim_in(room_with_docks(), Pose2D(-0.5, 0.0, 0.0), TB4)) == pytest.approx(
        2.0 - 0.5 - 0.171)  # without the dock: the wall behind
    at_contact = sim_in(docked_room, ORIGIN, TB4)
    assert 0.0 < simulator_clearance(at_contact) < 0.02  # resting against the dock's contacts
