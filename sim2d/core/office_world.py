"""Seeded generator of office-like worlds: two rows of rooms around an open hall, doors, columns.

Layout (m, map frame, centred on the origin; the hall runs along x)::

    +--------+------+---------+------+
    |  room  | room |  room   | room |   north row: rooms against the outer wall
    +---  ---+--  --+----  ---+-  ---+   front walls, one door per room facing the hall
    |    #          #          #     |   hall: open floor; square columns on a grid when deep enough
    +--  ----+---  -+-----  --+--  --+
    |  room  | room  |  room  | room |   south row
    +--------+-------+--------+------+

Why this shape: it has what navigation tests need from an office, in a form that is connected by
construction. Every room has exactly one door onto the hall and the hall spans the whole width,
so every room is reachable from the default spawn (tests check it on the rasterised grid). Narrow
doors test inflation and the controller, long halls test the planner, and columns give AMCL
features in open space. A small floor gives a corridor (no columns); a large one gives an open
depot floor with columns.

``dock=True`` adds a charging dock (sim2d.core.dock, a Create 3 dock) against the west wall of the
hall, facing west, 1 m south of the default spawn (less in a narrow hall): the robot's home, with
its 0.7 m straight approach on open floor (columns keep 1.6 m from every wall).

Deterministic: one ``np.random.Generator`` seeded with ``seed`` draws every random choice in a
fixed order, and coordinates are rounded to millimetres, so the same (seed, width, height) gives
the same world dict, and the same YAML, on every machine. Pure: numpy only; the dict is the
schema of ``sim2d.core.world`` (``parse_world`` accepts it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim2d.core.dock import CREATE3_DOCK

Box = tuple[float, float, float, float]
"""Axis-aligned box (xmin, ymin, xmax, ymax) (m)."""


@dataclass(frozen=True)
class OfficeParams:
    """Shape of generated offices (m).

    Attributes:
        wall_thickness: outer and interior walls.
        door_width: clear width of a door; at 1.0 m a waffle (0.24 m circumradius) keeps 0.26 m
            on each side, so planners find the door with the costmap's inflation on.
        door_margin: minimum wall left between a door and a room corner.
        room_width: (min, max) target room width along the hall; each row picks one target.
        room_depth: (min, max) room depth from the outer wall to the front wall's centre line.
        min_hall_width: the hall between the two rows is never narrower (centre line to centre line).
        column_size: side of the square columns.
        column_pitch: (min, max) spacing of the column grid; the seed picks one.
        column_clearance: minimum distance from a column centre to any wall, so columns never narrow
            a door's approach or the strip along the front walls.
    """

    wall_thickness: float = 0.15
    door_width: float = 1.0
    door_margin: float = 0.3
    room_width: tuple[float, float] = (2.6, 4.5)
    room_depth: tuple[float, float] = (2.8, 4.0)
    min_hall_width: float = 1.8
    column_size: float = 0.4
    column_pitch: tuple[float, float] = (4.0, 6.0)
    column_clearance: float = 1.6

    @property
    def smallest_room(self) -> float:
        """Narrowest room width (m) that still holds a door, its margins and a partition wall."""
        return self.door_width + 2.0 * self.door_margin + self.wall_thickness


@dataclass(frozen=True)
class Room:
    """One room: its interior (m) and the door gap in its front wall (m)."""

    interior: Box
    door: Box

    @property
    def centre(self) -> tuple[float, float]:
        """Centre of the interior (m)."""
        x0, y0, x1, y1 = self.interior
        return (round((x0 + x1) / 2.0, 3), round((y0 + y1) / 2.0, 3))


@dataclass(frozen=True)
class OfficeLayout:
    """A generated office: inner size (m), walls and columns as boxes, rooms, spawns (m, m, rad)."""

    width: float
    height: float
    wall_thickness: float
    walls: tuple[Box, ...]
    columns: tuple[Box, ...]
    rooms: tuple[Room, ...]
    spawns: tuple[tuple[float, float, float], ...]
    docks: tuple[tuple[str, tuple[float, float, float]], ...] = ()

    def world(self, name: str) -> dict[str, Any]:
        """The world dict (``sim2d.core.world`` schema): outer ring, interior boxes, spawns, docks.

        The ring and the free region get separate vertex lists, so a YAML dump has no anchors.
        """
        hx, hy = self.width / 2.0, self.height / 2.0
        inner = [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]
        ring = {"type": "ring", "vertices": [list(v) for v in inner], "thickness": self.wall_thickness}
        boxes = [{"type": "box", "min": [b[0], b[1]], "max": [b[2], b[3]]} for b in self.walls + self.columns]
        world: dict[str, Any] = {"name": name, "free_region": inner, "spawns": [list(s) for s in self.spawns]}
        if self.docks:
            world["docks"] = [{"id": dock_id, "type": CREATE3_DOCK.name, "pose": list(pose)}
                              for dock_id, pose in self.docks]
        return {**world, "obstacles": [ring, *boxes]}


def generate_office(width: float, height: float, seed: int,
                    params: OfficeParams | None = None, dock: bool = False) -> OfficeLayout:
    """An office of ``width`` × ``height`` (m, inside the outer walls) drawn from ``seed``; with
    ``dock``, a charging dock ``home_dock`` near the default spawn (drawn after everything else, so
    the rest of the office does not change).

    Raises:
        ValueError: the floor is too small for two rows of rooms and a hall.
    """
    p = params or OfficeParams()
    depth_limit = (height - p.min_hall_width) / 2.0
    if depth_limit < 2.0 or width < max(p.room_width[0], p.smallest_room):
        raise ValueError(f"office {width} x {height} m: too small for two rows of rooms and a "
                         f"{p.min_hall_width} m hall (need height >= {2 * 2.0 + p.min_hall_width} m, "
                         f"width >= {p.room_width[0]} m)")
    rng = np.random.default_rng(seed)
    hx, hy = width / 2.0, height / 2.0
    walls: list[Box] = []
    rooms: list[Room] = []
    fronts: list[float] = []
    for side in (1.0, -1.0):  # north row, then south row
        depth = float(rng.uniform(min(p.room_depth[0], depth_limit), min(p.room_depth[1], depth_limit)))
        front_y = side * (hy - depth)
        fronts.append(front_y)
        row_walls, row_rooms = _room_row(rng, p, hx, hy, side, front_y)
        walls += row_walls
        rooms += row_rooms
    hall = (-hx, fronts[1] + p.wall_thickness / 2.0, hx, fronts[0] - p.wall_thickness / 2.0)
    columns = _columns(rng, p, hall)
    hall_y = round((hall[1] + hall[3]) / 2.0, 3)
    default = (round(-hx + 0.8, 3), hall_y, 0.0)  # west end of the hall, facing along it
    in_rooms = [(*r.centre, round(-math.pi / 2.0 if r.centre[1] > 0.0 else math.pi / 2.0, 4)) for r in rooms]
    spawns = (default, *in_rooms)  # every room centre, facing its door
    # contact pose 0.25 m off the west wall (the dock's body, up to 0.22 m ahead of it, fits for every robot)
    south = min(DOCK_SPAWN_OFFSET, (hall[3] - hall[1]) / 2.0 - 0.4)
    docks = ((DOCK_ID, (round(-hx + DOCK_WALL_OFFSET, 3), round(hall_y - south, 3), round(math.pi, 4))),)
    return OfficeLayout(width, height, p.wall_thickness, tuple(walls), columns, tuple(rooms), spawns,
                        docks if dock else ())


DOCK_ID = "home_dock"
DOCK_WALL_OFFSET = 0.25  # m from the west wall to the dock's contact pose
DOCK_SPAWN_OFFSET = 1.0  # m south of the default spawn


def _room_row(rng: np.random.Generator, p: OfficeParams, hx: float, hy: float, side: float,
              front_y: float) -> tuple[list[Box], list[Room]]:
    """Partition and front walls of one row (``side`` +1 north, -1 south) and its rooms.

    The row is split into rooms of about one target width, each jittered by up to ±15 % so rooms
    differ (never so narrow that a door and its margins no longer fit); each front wall gets one
    door at a random offset, at least ``door_margin`` from the corners.
    """
    t = p.wall_thickness
    target = float(rng.uniform(*p.room_width))
    jitter = 0.15
    fitting = int(2.0 * hx * (1.0 - jitter) / (1.0 + jitter) // p.smallest_room)
    count = max(1, min(round(2.0 * hx / target), fitting))
    shares = 1.0 + rng.uniform(-jitter, jitter, count)
    edges = -hx + 2.0 * hx * np.concatenate(([0.0], np.cumsum(shares) / shares.sum()))
    front = (front_y - t / 2.0, front_y + t / 2.0)
    outer_y = side * hy
    walls: list[Box] = []
    rooms: list[Room] = []
    for i in range(count):
        x0, x1 = float(edges[i]), float(edges[i + 1])
        if i > 0:  # partition wall between this room and the previous one
            walls.append(_box(x0 - t / 2.0, min(front[0], outer_y), x0 + t / 2.0, max(front[1], outer_y)))
        inner_x0 = x0 + (t / 2.0 if i > 0 else 0.0)
        inner_x1 = x1 - (t / 2.0 if i < count - 1 else 0.0)
        low = inner_x0 + p.door_margin
        high = inner_x1 - p.door_margin - p.door_width
        door_x = float(rng.uniform(low, max(low, high)))
        door = _box(door_x, front[0], door_x + p.door_width, front[1])
        walls += [_box(x0, front[0], door[0], front[1]), _box(door[2], front[0], x1, front[1])]
        interior_y = (front[1], outer_y) if side > 0 else (outer_y, front[0])
        rooms.append(Room(_box(inner_x0, interior_y[0], inner_x1, interior_y[1]), door))
    return walls, rooms


def _columns(rng: np.random.Generator, p: OfficeParams, hall: Box) -> tuple[Box, ...]:
    """Square columns on a regular grid in the hall, at least ``column_clearance`` from every wall.

    None when the hall is too shallow: a corridor keeps its full width.
    """
    x0, y0, x1, y1 = hall
    pitch = float(rng.uniform(*p.column_pitch))
    c = p.column_clearance
    if x1 - x0 < 2.0 * c or y1 - y0 < 2.0 * c:
        return ()
    half = p.column_size / 2.0
    return tuple(_box(x - half, y - half, x + half, y + half)
                 for y in _grid_lines(y0 + c, y1 - c, pitch) for x in _grid_lines(x0 + c, x1 - c, pitch))


def _grid_lines(low: float, high: float, pitch: float) -> list[float]:
    """Evenly spaced positions from ``low`` to ``high`` (m), at least ``pitch`` apart; one: the middle."""
    count = int((high - low) // pitch) + 1
    if count == 1:
        return [(low + high) / 2.0]
    return [float(v) for v in np.linspace(low, high, count)]


def _box(x0: float, y0: float, x1: float, y1: float) -> Box:
    """A box with corners rounded to millimetres, so the YAML is stable across machines."""
    return (round(x0, 3), round(y0, 3), round(x1, 3), round(y1, 3))
