"""Worlds as data: load a world YAML (sim2d/worlds/*.yaml) or any map_server map as static geometry.

World YAML schema (all lengths m, angles rad, map frame)::

    name: turtlebot3_world
    free_region: [[x, y], ...]          # optional convex CCW polygon known free (map generation)
    spawns: [[x, y, yaw], ...]          # optional free poses; the first is the world's default
    docks:                              # optional charging docks (sim2d/core/dock.py)
      - {id: home_dock, type: create3_dock, pose: [x, y, yaw]}   # pose: the CONTACT pose of base_link
        # optional per dock: contact_tolerance (m), contact_yaw_tolerance (rad); default: the type's
    obstacles:
      - {type: circle, center: [x, y], radius: r}
      - {type: polygon, vertices: [[x, y], ...]}                 # convex, counter-clockwise
      - {type: regular_polygon, center: [x, y], circumradius: r, sides: n, rotation: a}
      - {type: box, min: [x, y], max: [x, y]}
      - {type: ring, vertices: [[x, y], ...], thickness: t}      # wall outside a convex CCW polygon

A map_server YAML (recognised by its ``image`` key) loads as a world whose occupied cells are the
obstacles; it has no free_region, no spawns and no docks. Errors name the file and the field, e.g.
``worlds/x.yaml: obstacles[2].radius: ...``; a spawn or a dock's contact pose inside an obstacle is such
an error too.

Docks are not part of ``geometry``: their bodies depend on the robot model (sim2d.core.dock), the
simulator adds them to its collision and lidar geometry, and a map generated from the world leaves
them out, as a real dock is usually not in the map.
``check_spawn`` refuses a robot pose that overlaps an obstacle, so a bad ``--x/--y`` fails at startup
instead of leaving the robot stuck inside a wall.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from navsuite_data import data_dir, resolve, searched
from sim2d.core.dock import DOCK_TYPES, Dock
from sim2d.core.geometry import FloatArray, StaticGeometry, is_convex_ccw, regular_polygon, ring_pieces
from sim2d.core.grid_shapes import map_to_geometry
from sim2d.core.map_io import load_map
from sim2d.core.robot import Pose2D

WORLDS_DIR = data_dir("worlds")  # the shipped worlds (navsuite_data; sim2d/worlds/ in the checkout)
Spawn = tuple[float, float, float]
"""A spawn pose (x, y, yaw) in the map frame (m, m, rad)."""


@dataclass(frozen=True)
class World:
    """A loaded world: its obstacles, the region known to be free, the file it came from, its spawns.

    ``spawns`` lists poses known to be free (the first is the default); ``docks`` the charging docks
    (sim2d.core.dock); both empty for map worlds.
    """

    name: str
    geometry: StaticGeometry
    free_region: FloatArray | None
    source: Path
    spawns: tuple[Spawn, ...] = ()
    docks: tuple[Dock, ...] = ()


def resolve_world(spec: str | Path) -> Path:
    """A world name (a shipped world, sim2d/worlds/NAME.yaml) or a path to a world or map_server YAML
    (relative to the working directory, else a shipped file of that name, e.g. ``maps/x.yaml``)."""
    path = resolve(spec)
    if path.suffix in (".yaml", ".yml"):
        if not path.is_file():
            raise ValueError(f"{spec}: world file not found ({searched(spec)})")
        return path
    named = WORLDS_DIR / f"{spec}.yaml"
    if not named.is_file():
        known = ", ".join(sorted(p.stem for p in WORLDS_DIR.glob("*.yaml")))
        raise ValueError(f"world {spec!r} not found in {WORLDS_DIR} (known: {known})")
    return named


def load_world(spec: str | Path) -> World:
    """Load a world by name or path; a map_server YAML becomes a grid world."""
    path = resolve_world(spec)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ValueError(f"{path}: cannot read world YAML ({exc})") from exc
    if isinstance(data, dict) and "image" in data:
        return World(path.stem, map_to_geometry(load_map(path)), None, path)
    return parse_world(data, path)


def parse_world(data: object, path: Path) -> World:
    """A world from the parsed mapping of a world YAML; ``path`` only names the source in errors.

    Why separate from ``load_world``: generated worlds (sim2d.core.office_world) are checked by the
    same rules before they are written to a file.
    """
    if not isinstance(data, dict) or not isinstance(data.get("obstacles"), list):
        raise ValueError(f"{path}: obstacles: missing or not a list of obstacles")
    out = _Shapes()
    for i, item in enumerate(data["obstacles"]):
        where = f"{path}: obstacles[{i}]"
        if not isinstance(item, dict) or item.get("type") not in _BUILDERS:
            raise ValueError(f"{where}.type: must be one of {sorted(_BUILDERS)}, got {item!r}")
        _BUILDERS[item["type"]](_Fields(item, where), out)
    free = None
    if "free_region" in data:
        free = _Fields(data, f"{path}").polygon("free_region")
    geometry = StaticGeometry(circles=np.array(out.circles, dtype=np.float64).reshape(-1, 3),
                              boxes=np.array(out.boxes, dtype=np.float64).reshape(-1, 4),
                              polygons=tuple(out.polygons))
    return World(str(data.get("name", path.stem)), geometry, free, path, _spawns(data, path, geometry),
                 _docks(data, path, geometry))


def check_spawn(world: World, x: float, y: float, radius: float) -> None:
    """Refuse a robot spawn at (x, y) (m, map frame) whose disc of ``radius`` (m) touches an obstacle.

    ``radius`` is the robot's footprint circumradius, so any yaw is safe. Why refuse: the simulator
    never pushes the robot out of an obstacle, so a robot spawned inside a wall is stuck there and
    every later failure (no motion, lost localization) hides the real cause.

    Raises:
        ValueError: one line naming the world file, the pose, the clearance and free alternatives.
    """
    point = np.array([[x, y]], dtype=np.float64)
    inside = bool(world.geometry.contains(point)[0])
    clearance = float(world.geometry.boundary_distance(point)[0])
    if not inside and clearance >= radius:
        return
    problem = (f"is inside an obstacle ({clearance:.2f} m from its edge)" if inside else
               f"is too close to an obstacle ({clearance:.2f} m clearance, the robot needs {radius:.2f} m)")
    spawns = ", ".join(f"({sx:g}, {sy:g}, {syaw:g})" for sx, sy, syaw in world.spawns)
    hint = f"e.g. the world's spawns: {spawns}" if spawns else "the world lists no spawns"
    raise ValueError(f"spawn ({x:g}, {y:g}) in {world.source} {problem}; pick a free pose, {hint}")


def _is_number(value: object) -> bool:
    """A finite int or float from YAML (not a bool)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and bool(np.isfinite(value))


def _spawns(data: dict[str, Any], path: Path, geometry: StaticGeometry) -> tuple[Spawn, ...]:
    """The ``spawns`` list: each [x, y, yaw] (m, m, rad), none inside an obstacle."""
    value = data.get("spawns", [])
    if not isinstance(value, list):
        raise ValueError(f"{path}: spawns: must be a list of [x, y, yaw], got {value!r}")
    spawns: list[Spawn] = []
    for i, item in enumerate(value):
        if not (isinstance(item, list) and len(item) == 3 and all(_is_number(v) for v in item)):
            raise ValueError(f"{path}: spawns[{i}]: must be [x, y, yaw] (m, m, rad), got {item!r}")
        spawns.append((float(item[0]), float(item[1]), float(item[2])))
    inside = geometry.contains(np.array([s[:2] for s in spawns], dtype=np.float64).reshape(-1, 2))
    if inside.any():
        i = int(np.argmax(inside))
        raise ValueError(f"{path}: spawns[{i}]: {value[i]} is inside an obstacle")
    return tuple(spawns)


_DOCK_FIELDS = ("id", "type", "pose", "contact_tolerance", "contact_yaw_tolerance")


def _docks(data: dict[str, Any], path: Path, geometry: StaticGeometry) -> tuple[Dock, ...]:
    """The ``docks`` list: each {id, type, pose: [x, y, yaw]} with a free contact pose and a unique id."""
    value = data.get("docks", [])
    if not isinstance(value, list):
        raise ValueError(f"{path}: docks: must be a list of {{id, type, pose}}, got {value!r}")
    docks: list[Dock] = []
    for i, item in enumerate(value):
        where = f"{path}: docks[{i}]"
        if not isinstance(item, dict):
            raise ValueError(f"{where}: must be a mapping {{id, type, pose}}, got {item!r}")
        unknown = sorted(str(key) for key in item if key not in _DOCK_FIELDS)
        if unknown:
            raise ValueError(f"{where}.{unknown[0]}: unknown field (known: {', '.join(_DOCK_FIELDS)})")
        dock_id = item.get("id")
        if not isinstance(dock_id, str) or not dock_id.strip():
            raise ValueError(f"{where}.id: must be a non-empty string, got {dock_id!r}")
        if any(dock.id == dock_id for dock in docks):
            raise ValueError(f"{where}.id: {dock_id!r} is already the id of an earlier dock")
        kind = item.get("type")
        if kind not in DOCK_TYPES:
            raise ValueError(f"{where}.type: must be one of {sorted(DOCK_TYPES)}, got {kind!r}")
        pose = item.get("pose")
        if not (isinstance(pose, list) and len(pose) == 3 and all(_is_number(v) for v in pose)):
            raise ValueError(f"{where}.pose: must be the contact pose [x, y, yaw] (m, m, rad), got {pose!r}")
        if geometry.contains(np.array([pose[:2]], dtype=np.float64))[0]:
            raise ValueError(f"{where}.pose: contact pose {pose} is inside an obstacle")
        dock_type = DOCK_TYPES[kind]
        fields = _Fields(item, where)
        docks.append(Dock(dock_id, dock_type, Pose2D(float(pose[0]), float(pose[1]), float(pose[2])),
                          fields.number("contact_tolerance", True, dock_type.contact_tolerance),
                          fields.number("contact_yaw_tolerance", True, dock_type.contact_yaw_tolerance)))
    return tuple(docks)


@dataclass
class _Shapes:
    """Obstacles collected while reading a world file."""

    circles: list[list[float]] = field(default_factory=list)
    boxes: list[list[float]] = field(default_factory=list)
    polygons: list[FloatArray] = field(default_factory=list)


class _Fields:
    """Typed access to one obstacle's fields with errors that name file, index and field."""

    def __init__(self, item: dict[str, Any], where: str) -> None:
        self.item, self.where = item, where

    def _get(self, key: str) -> Any:
        if key not in self.item:
            raise ValueError(f"{self.where}.{key}: missing")
        return self.item[key]

    def number(self, key: str, positive: bool = False, default: float | None = None) -> float:
        value = self.item.get(key, default) if default is not None else self._get(key)
        if not _is_number(value):
            raise ValueError(f"{self.where}.{key}: must be a number, got {value!r}")
        if positive and value <= 0:
            raise ValueError(f"{self.where}.{key}: must be > 0, got {value!r}")
        return float(value)

    def point(self, key: str) -> tuple[float, float]:
        value = self._get(key)
        if not (isinstance(value, list) and len(value) == 2 and all(_is_number(v) for v in value)):
            raise ValueError(f"{self.where}.{key}: must be [x, y], got {value!r}")
        return float(value[0]), float(value[1])

    def polygon(self, key: str) -> FloatArray:
        value = self._get(key)
        try:
            vertices = np.array(value, dtype=np.float64)
        except (TypeError, ValueError):
            vertices = np.zeros((0,))
        if vertices.ndim != 2 or vertices.shape[1] != 2 or not is_convex_ccw(vertices):
            raise ValueError(f"{self.where}.{key}: must be a convex counter-clockwise list of [x, y], "
                             f"got {value!r}")
        return vertices


def _circle(f: _Fields, out: _Shapes) -> None:
    out.circles.append([*f.point("center"), f.number("radius", positive=True)])


def _box(f: _Fields, out: _Shapes) -> None:
    low, high = f.point("min"), f.point("max")
    if not (high[0] > low[0] and high[1] > low[1]):
        raise ValueError(f"{f.where}.max: must exceed min in x and y, got min {low} max {high}")
    out.boxes.append([*low, *high])


def _polygon(f: _Fields, out: _Shapes) -> None:
    out.polygons.append(f.polygon("vertices"))


def _regular(f: _Fields, out: _Shapes) -> None:
    sides = f.item.get("sides")
    if not isinstance(sides, int) or isinstance(sides, bool) or sides < 3:
        raise ValueError(f"{f.where}.sides: must be an integer >= 3, got {sides!r}")
    out.polygons.append(regular_polygon(f.point("center"), f.number("circumradius", positive=True), sides,
                                    f.number("rotation", default=0.0)))


def _ring(f: _Fields, out: _Shapes) -> None:
    out.polygons.extend(ring_pieces(f.polygon("vertices"), f.number("thickness", positive=True)))


_BUILDERS: dict[str, Callable[[_Fields, _Shapes], None]] = {
    "circle": _circle, "box": _box, "polygon": _polygon, "regular_polygon": _regular, "ring": _ring,
}
