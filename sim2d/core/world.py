"""Worlds as data: load a world YAML (sim2d/worlds/*.yaml) or any map_server map as static geometry.

World YAML schema (all lengths m, angles rad, map frame)::

    name: turtlebot3_world
    free_region: [[x, y], ...]          # optional convex CCW polygon known free (map generation)
    obstacles:
      - {type: circle, center: [x, y], radius: r}
      - {type: polygon, vertices: [[x, y], ...]}                 # convex, counter-clockwise
      - {type: regular_polygon, center: [x, y], circumradius: r, sides: n, rotation: a}
      - {type: box, min: [x, y], max: [x, y]}
      - {type: ring, vertices: [[x, y], ...], thickness: t}      # wall outside a convex CCW polygon

A map_server YAML (recognised by its ``image`` key) loads as a world whose occupied cells are the
obstacles. Errors name the file and the field, e.g. ``worlds/x.yaml: obstacles[2].radius: ...``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from sim2d.core.geometry import FloatArray, StaticGeometry, is_convex_ccw, regular_polygon, ring_pieces
from sim2d.core.grid_shapes import map_to_geometry
from sim2d.core.map_io import load_map

WORLDS_DIR = Path(__file__).resolve().parents[1] / "worlds"


@dataclass(frozen=True)
class World:
    """A loaded world: its obstacles, the region known to be free, and the file it came from."""

    name: str
    geometry: StaticGeometry
    free_region: FloatArray | None
    source: Path


def resolve_world(spec: str | Path) -> Path:
    """A world name (file under sim2d/worlds/) or a path to a world or map_server YAML."""
    path = Path(spec)
    if path.suffix in (".yaml", ".yml"):
        if not path.is_file():
            raise ValueError(f"{path}: world file not found")
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
    return World(str(data.get("name", path.stem)), geometry, free, path)


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
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
            raise ValueError(f"{self.where}.{key}: must be a number, got {value!r}")
        if positive and value <= 0:
            raise ValueError(f"{self.where}.{key}: must be > 0, got {value!r}")
        return float(value)

    def point(self, key: str) -> tuple[float, float]:
        value = self._get(key)
        if not (isinstance(value, list) and len(value) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
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
