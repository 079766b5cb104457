"""Costmaps for the planning and control benchmarks (not library code).

The TurtleBot3 world comes from maps/turtlebot3_world.yaml when that file exists, otherwise it is
rasterised here from the geometry in reference/nav2.md §6 (9 pillars, hexagonal wall, 5 prisms).
Both are inflated with a small brute-force inflation (robot radius 0.22 m, inflation radius
0.70 m, cost_scaling_factor 3.0: the Jazzy global costmap) so the bench needs no costmap module.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml

from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION, GridSpec

MAPS = Path(__file__).resolve().parent.parent / "maps"
U8 = npt.NDArray[np.uint8]


def inflate(
    costs: U8,
    resolution: float,
    robot_radius: float = 0.22,
    inflation_radius: float = 0.70,
    cost_scaling_factor: float = 3.0,
) -> U8:
    """Nav2 inflation: 253 within the robot radius, 252·exp(-csf·(d − r)) out to the inflation radius."""
    lethal = costs == LETHAL_OBSTACLE
    reach = math.ceil(inflation_radius / resolution)
    h, w = costs.shape
    padded = np.zeros((h + 2 * reach, w + 2 * reach), dtype=bool)
    padded[reach : reach + h, reach : reach + w] = lethal
    dist = np.full(costs.shape, np.inf)
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            d = math.hypot(dx, dy) * resolution
            if d > inflation_radius:
                continue
            hit = padded[reach + dy : reach + dy + h, reach + dx : reach + dx + w]
            dist = np.where(hit & (d < dist), d, dist)
    out = costs.copy()
    ring = np.isfinite(dist) & ~lethal
    cost = np.where(
        dist <= robot_radius,
        INSCRIBED_INFLATED_OBSTACLE,
        np.floor(252.0 * np.exp(-cost_scaling_factor * (dist - robot_radius))),
    )
    out[ring] = np.maximum(out[ring], cost[ring].astype(np.uint8))
    return out


def _inside_hexagon(
    x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], cx: float, cy: float, circumradius: float
) -> npt.NDArray[np.bool_]:
    """Hexagon pointy along ±x."""
    dx, dy = np.abs(x - cx), np.abs(y - cy)
    s3 = math.sqrt(3.0)
    return (dy <= circumradius * s3 / 2) & (s3 * dx + dy <= s3 * circumradius)


def rasterised_turtlebot3_world() -> tuple[U8, GridSpec]:
    """Raw static costs (0 free, 254 occupied, 255 unknown outside the walls) of turtlebot3_world."""
    spec = GridSpec(384, 384, 0.05, -10.0, -10.0)
    mx, my = np.meshgrid(np.arange(spec.width), np.arange(spec.height))
    x, y = spec.cell_to_world(mx, my)
    inner_r = 2.933
    wall = 0.3175
    outer_r = (inner_r * math.sqrt(3) / 2 + wall) * 2 / math.sqrt(3)
    inside = _inside_hexagon(x, y, 0, 0, inner_r)
    occupied = _inside_hexagon(x, y, 0, 0, outer_r) & ~inside
    for px in (-1.1, 0.0, 1.1):
        for py in (-1.1, 0.0, 1.1):
            occupied |= np.hypot(x - px, y - py) <= 0.15
    occupied |= _inside_hexagon(x, y, 3.5, 0.0, 1.173)
    for sx in (-1.8, 1.8):
        for sy in (-2.7, 2.7):
            occupied |= _inside_hexagon(x, y, sx, sy, 0.807)
    costs = np.full(spec.shape, NO_INFORMATION, dtype=np.uint8)
    costs[inside] = 0
    costs[occupied] = LETHAL_OBSTACLE
    return costs, spec


def load_map_yaml(path: Path) -> tuple[U8, GridSpec]:
    """Trinary static costs from a map_server yaml + binary pgm (P5), rows flipped to y-up."""
    meta = yaml.safe_load(path.read_text())
    raw = (path.parent / meta["image"]).read_bytes()
    fields = raw.split(maxsplit=4)
    width, height = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(fields[4][-width * height :], dtype=np.uint8).reshape(height, width)[::-1]
    p = (255.0 - pixels) / 255.0 if not meta.get("negate", 0) else pixels / 255.0
    costs = np.full(p.shape, NO_INFORMATION, dtype=np.uint8)
    costs[p >= meta["occupied_thresh"]] = LETHAL_OBSTACLE
    costs[p <= meta["free_thresh"]] = 0
    ox, oy, oyaw = meta["origin"]
    return costs, GridSpec(width, height, float(meta["resolution"]), ox, oy, oyaw)


def turtlebot3_world_costmap() -> tuple[U8, GridSpec, str]:
    """Inflated TB3 world costmap and where it came from."""
    shipped = MAPS / "turtlebot3_world.yaml"
    if shipped.exists():
        costs, spec = load_map_yaml(shipped)
        source = "maps/turtlebot3_world.yaml"
    else:
        costs, spec = rasterised_turtlebot3_world()
        source = "rasterised from nav2.md §6 geometry"
    return inflate(costs, spec.resolution), spec, source


def random_obstacle_costmap(size: int, seed: int, n_obstacles: int = 400) -> tuple[U8, GridSpec]:
    """A size×size 0.05 m map with random rectangles and discs, inflated like the TB3 map."""
    rng = np.random.default_rng(seed)
    spec = GridSpec(size, size, 0.05)
    costs = np.zeros(spec.shape, dtype=np.uint8)
    yy, xx = np.mgrid[0:size, 0:size]
    for _ in range(n_obstacles):
        cx, cy = rng.integers(0, size, 2)
        if rng.random() < 0.5:
            hw, hh = rng.integers(2, 20, 2)
            costs[max(cy - hh, 0) : cy + hh, max(cx - hw, 0) : cx + hw] = LETHAL_OBSTACLE
        else:
            r = rng.integers(3, 15)
            sl = (slice(max(cy - r, 0), cy + r + 1), slice(max(cx - r, 0), cx + r + 1))
            disc = (xx[sl] - cx) ** 2 + (yy[sl] - cy) ** 2 <= r * r
            costs[sl][disc] = LETHAL_OBSTACLE
    return inflate(costs, spec.resolution), spec


def warehouse_costmap(seed: int, resolution: float = 0.03, size: tuple[float, float] = (30.0, 50.0)
                      ) -> tuple[U8, GridSpec]:
    """A warehouse floor at ``resolution`` m: racks in rows along y, aisles between them, cross aisles,
    scattered pallets in the aisles, inflated like the TB3 map.

    Why: issue 19's second large map. At 3 cm a 30 m × 50 m hall is 1000 × 1667 cells (1.67 million),
    and its long racks force detours that a random-obstacle map does not. Sizes are in m.
    Layout (all from ``seed``): a 0.3 m outer wall; racks 1.0 m deep and 5 to 9 m long, in columns
    3.6 m apart (a 2.6 m aisle), broken by 2.4 m cross aisles every 10 to 14 m; 60 pallets of
    0.8 m × 1.2 m (either way round) placed at random, some narrowing the aisles.
    """
    rng = np.random.default_rng(seed)
    width, height = round(size[0] / resolution), round(size[1] / resolution)
    spec = GridSpec(width, height, resolution)
    costs = np.zeros(spec.shape, dtype=np.uint8)

    def block(x0: float, y0: float, x1: float, y1: float) -> None:
        """Mark the rectangle [x0, x1] × [y0, y1] (m) lethal."""
        c0, c1 = max(int(x0 / resolution), 0), min(math.ceil(x1 / resolution), width)
        r0, r1 = max(int(y0 / resolution), 0), min(math.ceil(y1 / resolution), height)
        costs[r0:r1, c0:c1] = LETHAL_OBSTACLE

    wall = 0.3
    block(0.0, 0.0, size[0], wall)
    block(0.0, size[1] - wall, size[0], size[1])
    block(0.0, 0.0, wall, size[1])
    block(size[0] - wall, 0.0, size[0], size[1])
    rack_depth, pitch = 1.0, 3.6
    x = 2.5
    while x + rack_depth < size[0] - 2.5:
        y = 2.5 + float(rng.uniform(0.0, 1.0))
        while y < size[1] - 2.5:
            length = float(rng.uniform(5.0, 9.0))
            block(x, y, x + rack_depth, min(y + length, size[1] - 2.5))
            y += length + 2.4 + float(rng.uniform(0.0, 3.0))  # a cross aisle
        x += pitch
    for _ in range(60):
        px, py = rng.uniform(1.0, size[0] - 2.0), rng.uniform(1.0, size[1] - 2.0)
        w, h = (0.8, 1.2) if rng.random() < 0.5 else (1.2, 0.8)
        block(float(px), float(py), float(px) + w, float(py) + h)
    return inflate(costs, resolution), spec
