"""Waypoint lists from YAML or a flat parameter (pure Python; errors name the file, index and field).

YAML form (``waypoints:`` at the top, each with ``x``, ``y`` in m and optional ``yaw`` in rad, ``name``)::

    waypoints:
      - {name: dock, x: -2.0, y: -0.5, yaw: 0.0}
      - {x: 2.0, y: 0.0}

Parameter form: a ``double[]`` of x, y, yaw triples.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml


@dataclass(frozen=True)
class Waypoint:
    """A named goal pose (m, m, rad) in the map frame."""

    x: float
    y: float
    yaw: float = 0.0
    name: str = ""


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{where} must be a finite number, got {value!r}")
    return float(value)


def parse_waypoints(data: Any, source: str) -> list[Waypoint]:
    """Waypoints from parsed YAML (``{'waypoints': [...]}`` or the list itself)."""
    items = data.get("waypoints") if isinstance(data, dict) else data
    if not isinstance(items, list):
        raise ValueError(f"{source}: expected a 'waypoints' list, got {type(items).__name__}")
    waypoints = []
    for i, item in enumerate(items):
        where = f"{source}: waypoints[{i}]"
        if not isinstance(item, dict):
            raise ValueError(f"{where} must be a mapping with x, y[, yaw, name], got {item!r}")
        for key in ("x", "y"):
            if key not in item:
                raise ValueError(f"{where} has no '{key}'")
        waypoints.append(
            Waypoint(
                _number(item["x"], f"{where}.x"),
                _number(item["y"], f"{where}.y"),
                _number(item.get("yaw", 0.0), f"{where}.yaw"),
                str(item.get("name", "")),
            )
        )
    return waypoints


def load_waypoints_file(path: str | Path) -> list[Waypoint]:
    """Read a waypoints YAML file."""
    try:
        text = Path(path).read_text()
    except OSError as error:
        raise ValueError(f"cannot read waypoints file {path}: {error.strerror}") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise ValueError(f"{path}: invalid YAML: {error}") from None
    return parse_waypoints(data, str(path))


def waypoints_from_flat(values: Sequence[float], source: str) -> list[Waypoint]:
    """Waypoints from x, y, yaw triples."""
    if len(values) % 3:
        raise ValueError(f"{source} must hold x, y, yaw triples; got {len(values)} numbers")
    return [
        Waypoint(float(values[i]), float(values[i + 1]), float(values[i + 2]))
        for i in range(0, len(values), 3)
    ]
