"""Can the waffle reach a location? Footprint clearance to turtlebot3_world's pillars and the
static-map costmap cost at the pose, with Nav2's semantics.

Two criteria (reference/nav2.md §4 and §6):

* collision-free: the footprint (circle of ``robot_radius`` 0.22 m) must not touch a pillar
  (r 0.15 m at x, y ∈ {-1.1, 0, 1.1}), i.e. the centre is more than 0.22 + 0.15 = 0.37 m from
  every pillar centre;
* reachable by the planner: the global costmap cost of the goal cell is below
  INSCRIBED_INFLATED_OBSTACLE (253): the distance from the goal cell's centre to the nearest lethal
  cell of the map exceeds the inscribed radius.

``python -m nav_stack.ros.autonomy.clearance [locations.yaml]`` prints the table used in the README.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nav_stack.core.costmap.inflation_layer import inflation_cost
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE
from nav_stack.core.map_io import OccupancyMap, load_map
from nav_stack.ros.autonomy.locations import Location, load_locations
from navsuite_data import config_path, map_path

DEFAULT_MAP = map_path("turtlebot3_world.yaml")
TB3_WORLD_PILLARS: tuple[tuple[float, float], ...] = tuple(
    (x, y) for x in (-1.1, 0.0, 1.1) for y in (-1.1, 0.0, 1.1)
)
PILLAR_RADIUS = 0.15  # m, turtlebot3_world cylinders
LETHAL_OCCUPANCY = 65  # map_server trinary: occupied_thresh 0.65 → 100; ≥ 65 counts as lethal


@dataclass(frozen=True)
class CostmapModel:
    """The global costmap knobs that decide reachability (config/nav2_params.yaml values)."""

    robot_radius: float = 0.22
    inflation_radius: float = 0.70
    cost_scaling_factor: float = 3.0


@dataclass(frozen=True)
class Clearance:
    """Clearance figures of one pose (distances in m)."""

    name: str
    pillar_centre_distance: float  # to the nearest pillar centre
    footprint_gap: float  # pillar_centre_distance − robot_radius − pillar radius (> 0: collision-free)
    lethal_distance: float  # goal cell centre to the nearest lethal map cell centre
    cost: int  # Nav2 inflation cost of the goal cell (253 inscribed, 254 lethal)

    @property
    def collision_free(self) -> bool:
        """The footprint does not touch a pillar."""
        return self.footprint_gap > 0.0

    @property
    def reachable(self) -> bool:
        """The planner may end a path in the goal cell (cost < 253)."""
        return self.cost < INSCRIBED_INFLATED_OBSTACLE


def pillar_distance(x: float, y: float, pillars: Iterable[tuple[float, float]] = TB3_WORLD_PILLARS) -> float:
    """Distance (m) from (x, y) to the nearest pillar centre."""
    return min(math.hypot(x - px, y - py) for px, py in pillars)


def lethal_distance(grid: OccupancyMap, x: float, y: float) -> float:
    """Distance (m) from the centre of the cell holding (x, y) to the nearest lethal cell centre."""
    rows, cols = np.nonzero(grid.data >= LETHAL_OCCUPANCY)
    if rows.size == 0:
        return math.inf
    wx, wy = grid.spec.cell_to_world(cols, rows)
    mx, my = grid.spec.world_to_cell(x, y)
    cx, cy = grid.spec.cell_to_world(mx, my)
    return float(np.min(np.hypot(wx - cx, wy - cy)))


def clearance(location: Location, grid: OccupancyMap, model: CostmapModel = CostmapModel()) -> Clearance:
    """Both criteria for one location."""
    centre = pillar_distance(location.x, location.y)
    lethal = lethal_distance(grid, location.x, location.y)
    cost = int(inflation_cost(lethal, model.robot_radius, model.cost_scaling_factor))
    if lethal > model.inflation_radius:
        cost = 0
    gap = centre - model.robot_radius - PILLAR_RADIUS
    return Clearance(location.name, centre, gap, lethal, cost)


def clearance_table(locations: Mapping[str, Location], grid: OccupancyMap,
                    model: CostmapModel = CostmapModel()) -> list[Clearance]:
    """``clearance`` of every location, in file order."""
    return [clearance(loc, grid, model) for loc in locations.values()]


def format_table(rows: Sequence[Clearance], locations: Mapping[str, Location]) -> str:
    """A Markdown table of the figures."""
    lines = ["| location | x | y | theta | pillar centre (m) | footprint gap (m) | lethal cell (m) | cost "
             "| ok |", "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        loc = locations[row.name]
        ok = "yes" if row.collision_free and row.reachable else "NO"
        lines.append(f"| {row.name} | {loc.x:g} | {loc.y:g} | {loc.theta:g} "
                     f"| {row.pillar_centre_distance:.3f} | {row.footprint_gap:+.3f} "
                     f"| {row.lethal_distance:.3f} | {row.cost} | {ok} |")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    path = Path(args[0]) if args else config_path("locations.yaml")
    locations = load_locations(path)
    print(format_table(clearance_table(locations, load_map(DEFAULT_MAP)), locations))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
