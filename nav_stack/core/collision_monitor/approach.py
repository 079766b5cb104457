"""The approach model: how long until the robot's footprint, driven by the command, meets the data.

Nav2's algorithm (nav2_collision_monitor kinematics and Polygon::getCollisionTime): the robot starts
at the origin of the base frame and is moved by the command in steps of ``simulation_time_step``.
Each step first moves the position by the velocity vector and turns the heading by ``w·dt``, then
turns the velocity vector by the same angle (so a command with w != 0 drives an arc of constant
speed). After each step the data points are expressed in the moved robot frame and counted inside
the footprint; the first step with ``min_points`` inside gives the collision time. Two details are
kept because they shape the output:

* the time reported for a step is the simulated time *before* it (0 for the first step), so the
  answer is rounded down to the step grid; a footprint already holding ``min_points`` before any
  motion gives 0;
* the loop runs while the accumulated time is ``<= time_before_collision``, summing the step as
  Nav2's ``time += dt`` does (so 0.1 s steps over 1.2 s also try the thirteenth step).

The monitor then scales the whole command by ``collision_time / time_before_collision``: at the new
speed the contact is ``time_before_collision`` away. Units: m, rad, s, m/s, rad/s.
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.collision_monitor.shapes import Zone
from nav_stack.core.geometry import FloatArray

NO_COLLISION = -1.0


def simulated_poses(vx: float, vy: float, wz: float, dt: float, steps: int) -> FloatArray:
    """Poses (steps, 3) ``[x, y, theta]`` after each of ``steps`` steps of ``dt`` from the origin.

    The velocity vector (vx, vy) is expressed in the starting frame and turned by ``wz·dt`` after
    each step, Nav2's projectState.
    """
    k = np.arange(steps, dtype=np.float64)
    heading = wz * dt * k  # the velocity's direction during step k
    step_x = (vx * np.cos(heading) - vy * np.sin(heading)) * dt
    step_y = (vx * np.sin(heading) + vy * np.cos(heading)) * dt
    return np.column_stack([np.cumsum(step_x), np.cumsum(step_y), wz * dt * (k + 1.0)])


def points_in_poses(points: FloatArray, poses: FloatArray) -> FloatArray:
    """``points`` (N, 2) expressed in each frame of ``poses`` (K, 3) → (K, N, 2)."""
    c, s = np.cos(poses[:, 2:3]), np.sin(poses[:, 2:3])
    dx = points[None, :, 0] - poses[:, 0:1]
    dy = points[None, :, 1] - poses[:, 1:2]
    return np.stack([dx * c + dy * s, -dx * s + dy * c], axis=-1)


def step_times(dt: float, horizon: float) -> list[float]:
    """The times Nav2's loop reports: 0, dt, 2·dt, ... summed as it sums them, while <= horizon."""
    times, t = [], 0.0
    while t <= horizon:
        times.append(t)
        t += dt
    return times


def collision_time(zone: Zone, points: FloatArray, velocity: tuple[float, float, float]) -> float:
    """Seconds until ``zone`` (the footprint) holds ``min_points`` of ``points`` (N, 2) while the
    robot follows ``velocity`` (vx, vy, wz); NO_COLLISION (-1) if not within
    ``time_before_collision``."""
    p = zone.params
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if zone.triggered(pts):
        return 0.0
    times = step_times(p.simulation_time_step, p.time_before_collision)
    if not times or len(pts) == 0:
        return NO_COLLISION
    vx, vy, wz = velocity
    poses = simulated_poses(vx, vy, wz, p.simulation_time_step, len(times))
    counts = np.count_nonzero(zone.inside(points_in_poses(pts, poses)), axis=1)
    hits = np.flatnonzero(counts >= zone.min_points)
    return times[int(hits[0])] if len(hits) else NO_COLLISION


def approach_ratio(time: float, time_before_collision: float) -> float | None:
    """The factor the command is scaled by for a collision ``time`` s ahead; None when no collision."""
    if time < 0.0 or not math.isfinite(time):
        return None
    return time / time_before_collision
