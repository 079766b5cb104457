"""The locations file of the seed project (``name: [x, y, theta]``, map frame) and its validation.

Why a module of its own: the seed re-read the YAML inside every ``GoToPose.onStart`` and a typo
surfaced as a robot that never moved. Here the file is read once at startup, every entry is
checked, and every ``loc`` port of the tree is checked against it, so each mistake is one line
naming the file and the item before the first tick. No ROS here: the unit tests use it directly.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import yaml

from nav_stack.core.bt import Tree
from nav_stack.core.bt.ports import blackboard_key

LOCATION_PORT = "loc"


class LocationsError(ValueError):
    """A locations file cannot be used; the message names the file and the item."""


@dataclass(frozen=True)
class Location:
    """A named goal pose in the map frame: x, y in m, theta (yaw) in rad."""

    name: str
    x: float
    y: float
    theta: float


def parse_locations(doc: object, source: str) -> dict[str, Location]:
    """Validate a parsed YAML document: a non-empty mapping of name → three finite numbers.

    Raises:
        LocationsError: naming ``source`` and the offending item.
    """
    if not isinstance(doc, Mapping) or not doc:
        raise LocationsError(f"{source}: expected a mapping 'name: [x, y, theta]', got {type(doc).__name__}"
                             + ("" if doc else " (empty file)"))
    locations: dict[str, Location] = {}
    for name, value in doc.items():
        if not isinstance(name, str) or not name:
            raise LocationsError(f"{source}: location name {name!r} is not a non-empty string")
        if not isinstance(value, (list, tuple)) or len(value) != 3:
            raise LocationsError(f"{source}: location '{name}': expected [x, y, theta], got {value!r}")
        numbers = []
        for axis, item in zip(("x", "y", "theta"), value, strict=True):
            if isinstance(item, bool) or not isinstance(item, (int, float)) or not math.isfinite(item):
                raise LocationsError(f"{source}: location '{name}': {axis} must be a finite number, "
                                     f"got {item!r}")
            numbers.append(float(item))
        locations[name] = Location(name, *numbers)
    return locations


def load_locations(path: str | Path) -> dict[str, Location]:
    """Read and validate a locations YAML file (see ``parse_locations``)."""
    file = Path(path)
    try:
        text = file.read_text()
    except OSError as exc:
        raise LocationsError(f"{file}: cannot read the locations file: {exc.strerror or exc}") from None
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{file}:{mark.line + 1}" if mark is not None else str(file)
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise LocationsError(f"{where}: {problem}") from None
    return parse_locations(doc, str(file))


def referenced_locations(tree: Tree) -> list[tuple[str, str]]:
    """``(location, where)`` for every literal ``loc`` port in the tree (``where``: node and file:line).

    Ports that point to the blackboard (``loc="{target}"``) are resolved at run time and skipped.
    """
    found = []
    for node in tree.nodes:
        raw = node.config.ports.get(LOCATION_PORT)
        if LOCATION_PORT in node.config.manifest and isinstance(raw, str) and blackboard_key(raw) is None:
            found.append((raw, f"{node.registration_id} '{node.name}' ({node.config.source})"))
    return found


def check_tree_locations(tree: Tree, locations: Mapping[str, Location], source: str) -> None:
    """Every literal ``loc`` of the tree must name a location of ``source``.

    Raises:
        LocationsError: the first missing location, the node that uses it and what is defined.
    """
    for name, where in referenced_locations(tree):
        if name not in locations:
            raise LocationsError(f"{source}: location '{name}' used by {where} is not defined "
                                 f"(defined: {', '.join(sorted(locations))})")


def nearest_location(locations: Iterable[Location], x: float, y: float, tolerance: float) -> str | None:
    """Name of the location within ``tolerance`` m of (x, y), or None (used to name visited goals)."""
    best, best_d = None, tolerance
    for loc in locations:
        d = math.hypot(loc.x - x, loc.y - y)
        if d <= best_d:
            best, best_d = loc.name, d
    return best
