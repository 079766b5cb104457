"""A tiny vectorised lidar over an occupancy grid, and synthetic worlds, for nav_stack unit tests.

Independent of nav_stack's own ray tracing on purpose: it marches every beam in quarter-cell steps
and reports the first occupied (value 100) cell, so the filters under test meet scans that were
not produced by the code they are checking.
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.grid import GridSpec


def cast_ranges(
    occupancy: np.ndarray,
    spec: GridSpec,
    pose: tuple[float, float, float],
    angles: np.ndarray,
    range_max: float,
    noise_std: float = 0.0,
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    """Range (m) to the first occupied cell along each beam from ``pose``; inf if none within range_max."""
    step = spec.resolution / 4.0
    t = np.arange(0.0, range_max + step, step)
    heading = pose[2] + angles
    xs = pose[0] + np.cos(heading)[:, None] * t[None, :]
    ys = pose[1] + np.sin(heading)[:, None] * t[None, :]
    mx, my = spec.world_to_cell(xs, ys)
    inside = spec.in_bounds(mx, my)
    hit = np.zeros(xs.shape, dtype=bool)
    hit[inside] = occupancy[my[inside], mx[inside]] == 100
    first = np.argmax(hit, axis=1)
    ranges = np.where(hit.any(axis=1), t[first], np.inf)
    if noise_std > 0.0 and rng is not None:
        ranges = ranges + rng.normal(0.0, noise_std, ranges.shape)
    return ranges


def fake_scan(
    occupancy: np.ndarray,
    spec: GridSpec,
    pose: tuple[float, float, float],
    beams: int = 360,
    range_min: float = 0.12,
    range_max: float = 3.5,
    noise_std: float = 0.0,
    rng: np.random.Generator | None = None,
) -> LaserScan:
    """A 360° scan (TB3 LDS-like) taken at ``pose`` (the laser frame = the robot frame)."""
    increment = 2.0 * math.pi / beams
    angles = np.arange(beams) * increment
    ranges = cast_ranges(occupancy, spec, pose, angles, range_max, noise_std, rng)
    return LaserScan(ranges, 0.0, increment, range_min, range_max)


def corridor_world(
    length: float = 10.0, width: float = 2.0, resolution: float = 0.05
) -> tuple[np.ndarray, GridSpec]:
    """A walled corridor along x with bumps of varying width every 1.1 m, so it can be localised in."""
    spec = GridSpec(
        round((length + 1.0) / resolution), round((width + 1.0) / resolution), resolution, -0.5, -0.5
    )
    grid = np.zeros(spec.shape, dtype=np.int8)
    grid[:8, :] = -1  # thin (2-cell) walls with unknown space behind them, as in a SLAM map
    grid[-8:, :] = -1
    grid[:, :8] = -1
    grid[:, -8:] = -1
    grid[8:10, 8:-8] = 100
    grid[-10:-8, 8:-8] = 100
    grid[8:-8, 8:10] = 100
    grid[8:-8, -10:-8] = 100
    for i, x in enumerate(np.arange(1.0, length, 1.1)):
        half = 2 + (i * 3) % 5  # bumps of different widths (cells), alternating sides
        y0, y1 = (0.0, 0.25) if i % 2 == 0 else (width - 0.25, width)
        mx0, my0 = spec.world_to_cell(x - half * resolution, y0)
        mx1, my1 = spec.world_to_cell(x + half * resolution, y1)
        grid[int(my0) : int(my1) + 1, int(mx0) : int(mx1) + 1] = 100
    return grid, spec


def pillar_world(resolution: float = 0.05) -> tuple[np.ndarray, GridSpec]:
    """A 6 m × 6 m walled room with a 3 × 3 grid of round pillars (r 0.15 m) a box and a wall stub."""
    spec = GridSpec(round(6.0 / resolution), round(6.0 / resolution), resolution, -3.0, -3.0)
    gy, gx = np.mgrid[0 : spec.height, 0 : spec.width]
    wx, wy = spec.cell_to_world(gx, gy)
    grid = np.zeros(spec.shape, dtype=np.int8)
    wall = (np.abs(wx) > 2.8) | (np.abs(wy) > 2.8)
    grid[wall] = 100
    for px in (-1.1, 0.0, 1.1):
        for py in (-1.1, 0.0, 1.1):
            grid[np.hypot(wx - px, wy - py) <= 0.15] = 100
    grid[(wx > 1.8) & (wx < 2.4) & (wy > -2.5) & (wy < -1.9)] = 100
    grid[(wx < -1.6) & (wy > 1.45) & (wy < 1.6)] = 100  # a wall stub breaking the point symmetry
    return grid, spec


def clutter_world(seed: int = 7, boxes: int = 14, resolution: float = 0.05) -> tuple[np.ndarray, GridSpec]:
    """A 6 m × 6 m walled room with randomly placed boxes: no two places look alike (kidnap tests)."""
    spec = GridSpec(round(6.0 / resolution), round(6.0 / resolution), resolution, -3.0, -3.0)
    gy, gx = np.mgrid[0 : spec.height, 0 : spec.width]
    wx, wy = spec.cell_to_world(gx, gy)
    grid = np.zeros(spec.shape, dtype=np.int8)
    grid[(np.abs(wx) > 2.8) | (np.abs(wy) > 2.8)] = 100
    rng = np.random.default_rng(seed)
    for _ in range(boxes):
        cx, cy = rng.uniform(-2.5, 2.5, 2)
        hx, hy = rng.uniform(0.08, 0.3, 2)
        grid[(np.abs(wx - cx) < hx) & (np.abs(wy - cy) < hy)] = 100
    return grid, spec
