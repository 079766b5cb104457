"""Ground-truth clearance: the smallest distance (m) from the robot's body to any obstacle.

Why the simulator computes it: a test that claims "the robot stopped 5 cm short of the box" needs a
distance nobody in the stack estimated. The simulator knows the true pose, the footprint it collides
with (RobotModel.footprint, the polygon pymunk uses) and every obstacle: the world's static shapes,
the dock bodies and the obstacles dropped at run time. The lidar's geometry holds all three
(Simulator keeps it current), so that is the geometry measured against.

How: the footprint's edges against the obstacles' straight edges (the lidar's segments, which trace
every polygon, box and map boundary), and against the round obstacles:

* two segments are 0 apart when they cross, else as far apart as the nearest end of one is from the
  other (corner-to-edge, both ways);
* a circle is its centre's distance to the footprint, less its radius (0 when they overlap).

The collision model never lets the robot into an obstacle, so crossing outlines (0) are the deepest
case. Only the obstacles whose bounding boxes come within ``CULL_RANGE`` of the footprint's are
measured first; when none of those is that close, everything is, so the answer is always exact.
Why not StaticGeometry.boundary_distance: it rebuilds every obstacle's edges on each call and has no
cull; built on it, this module was 3 to 4 times slower (measured side by side while writing it).
Cost: about 20 physics steps per evaluation (bench/bench_clearance.py), so the node evaluates it with
each odometry message, not every physics step.
Units: m, map frame.
"""

from __future__ import annotations

import math

import numpy as np

from sim2d.core.geometry import BoolArray, FloatArray, StaticGeometry, points_in_convex, polygon_edges
from sim2d.core.robot import Pose2D, RobotModel
from sim2d.core.simulator import Simulator

#: m: obstacles whose bounding box is farther than this from the footprint's are measured only when
#: nothing nearer is found (a cull for speed; the result does not depend on it).
CULL_RANGE = 1.0


def placed_footprint(robot: RobotModel, pose: Pose2D) -> FloatArray:
    """The robot's collision outline (k, 2) in the map frame at ``pose`` (counter-clockwise)."""
    local = np.array(robot.footprint(), dtype=np.float64)
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    return np.column_stack((pose.x + c * local[:, 0] - s * local[:, 1],
                            pose.y + s * local[:, 0] + c * local[:, 1]))


def _cross(u: FloatArray, v: FloatArray) -> FloatArray:
    result: FloatArray = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    return result


def point_segment_distance(points: FloatArray, segments: FloatArray) -> FloatArray:
    """Distance (P, S) (m) from each of ``points`` (P, 2) to each of ``segments`` (S, 4) [x0, y0, x1, y1]."""
    start = segments[None, :, 0:2]
    along = segments[None, :, 2:4] - start
    rel = points[:, None, :] - start
    length2 = np.maximum(np.sum(along * along, axis=2), 1e-18)
    t = np.clip(np.sum(rel * along, axis=2) / length2, 0.0, 1.0)
    gap = rel - t[:, :, None] * along
    result: FloatArray = np.sqrt(np.sum(gap * gap, axis=2))
    return result


def segments_cross(a: FloatArray, b: FloatArray) -> BoolArray:
    """(F, N): whether segment i of ``a`` (F, 4) meets segment j of ``b`` (N, 4), touching included.

    Orientation test: each segment's ends lie on opposite sides of (or on) the other's line.
    Collinear overlaps are left to the end-to-segment distances, which are 0 there.
    """
    p, r = a[:, None, 0:2], a[:, None, 2:4] - a[:, None, 0:2]
    q, s = b[None, :, 0:2], b[None, :, 2:4] - b[None, :, 0:2]
    side_b0, side_b1 = _cross(r, q - p), _cross(r, q + s - p)  # b's ends against a's line
    side_a0, side_a1 = _cross(s, p - q), _cross(s, p + r - q)  # a's ends against b's line
    result: BoolArray = (side_b0 * side_b1 <= 0.0) & (side_a0 * side_a1 <= 0.0) \
        & ((side_b0 != 0.0) | (side_b1 != 0.0))
    return result


def _segment_clearance(footprint: FloatArray, segments: FloatArray) -> float:
    """Smallest distance (m) from the polygon ``footprint`` (k, 2) to ``segments`` (N, 4); inf if none."""
    if len(segments) == 0:
        return math.inf
    edges = polygon_edges(footprint)
    if bool(np.any(segments_cross(edges, segments))):
        return 0.0
    corners_to_obstacles = point_segment_distance(footprint, segments)
    ends = np.concatenate((segments[:, 0:2], segments[:, 2:4]))
    if bool(np.any(points_in_convex(ends, footprint))):  # an obstacle edge wholly inside the body
        return 0.0
    obstacles_to_edges = point_segment_distance(ends, edges)
    return float(min(corners_to_obstacles.min(), obstacles_to_edges.min()))


def _circle_clearance(footprint: FloatArray, circles: FloatArray) -> float:
    """Smallest distance (m) from the convex CCW ``footprint`` (k, 2) to ``circles`` (M, 3); inf if none."""
    if len(circles) == 0:
        return math.inf
    centres = circles[:, 0:2]
    to_body = point_segment_distance(centres, polygon_edges(footprint)).min(axis=1)
    to_body[points_in_convex(centres, footprint)] = 0.0
    return float(np.min(to_body - circles[:, 2]))


def _near(low: FloatArray, high: FloatArray, box_low: FloatArray, box_high: FloatArray,
          reach: float) -> BoolArray:
    """Which boxes [low, high] (n, 2) come within ``reach`` (m) of the box [box_low, box_high]."""
    gap = np.maximum(np.maximum(low - box_high, box_low - high), 0.0)
    result: BoolArray = np.hypot(gap[:, 0], gap[:, 1]) <= reach
    return result


def footprint_clearance(footprint: FloatArray, geometry: StaticGeometry) -> float:
    """Smallest distance (m) from the convex CCW polygon ``footprint`` (k, 2) to ``geometry``'s
    obstacles (its lidar segments and circles); 0 when they touch or overlap; inf without obstacles."""
    segments, circles = geometry.ray_segments, geometry.circles
    box_low, box_high = footprint.min(axis=0), footprint.max(axis=0)
    near_segments = _near(np.minimum(segments[:, 0:2], segments[:, 2:4]),
                          np.maximum(segments[:, 0:2], segments[:, 2:4]), box_low, box_high, CULL_RANGE)
    near_circles = _near(circles[:, 0:2] - circles[:, 2:3], circles[:, 0:2] + circles[:, 2:3],
                         box_low, box_high, CULL_RANGE)
    nearest = min(_segment_clearance(footprint, segments[near_segments]),
                  _circle_clearance(footprint, circles[near_circles]))
    if nearest > CULL_RANGE:  # nothing within the cull: measure everything
        nearest = min(_segment_clearance(footprint, segments), _circle_clearance(footprint, circles))
    return max(nearest, 0.0)


def robot_clearance(robot: RobotModel, pose: Pose2D, geometry: StaticGeometry) -> float:
    """The clearance (m) of ``robot`` at ``pose`` (map frame) in ``geometry`` (Simulator.lidar.geometry
    holds the world, the docks and the dropped obstacles)."""
    return footprint_clearance(placed_footprint(robot, pose), geometry)


def simulator_clearance(sim: Simulator) -> float:
    """The simulated robot's clearance (m) now: its true pose against everything its lidar sees."""
    return robot_clearance(sim.robot, sim.pose, sim.lidar.geometry)
