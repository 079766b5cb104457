"""The dock database: dock instances (where each dock is, and its type) and the dock plugins by type.

Nav2's docking server keeps two maps: dock *instances* by name, read from the ``docks`` parameter list
or from a YAML file (``dock_database``, also reloadable at run time), and dock *plugins* (the models
that detect and judge a dock type) by their name in ``dock_plugins``. A DockRobot goal names an
instance (``dock_id``) or gives a pose and a type; either way the plugin comes from the type, and a
request that names no type works when exactly one plugin exists.

A dock file looks like Nav2's::

    docks:
      home_dock:
        type: simple_charging_dock   # a name from dock_plugins
        frame: map                   # optional, default map
        pose: [0.0, 0.0, 0.0]        # x (m), y (m), yaw (rad)
        id: c67f50cb                 # optional

Errors name the source (file or parameters), the dock and the field.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Generic, TypeVar

import yaml

from nav_stack.core.docking.errors import DockNotInDB, DockNotValid
from nav_stack.core.geometry import Pose2D

P = TypeVar("P")
DEFAULT_FRAME = "map"


class DockDatabaseError(ValueError):
    """A dock definition (file or parameters) is malformed; the message names the source and field."""


@dataclass(frozen=True)
class Dock:
    """One dock instance: its name, plugin type, frame and pose (x m, y m, yaw rad) in that frame."""

    name: str
    type: str
    frame: str
    pose: Pose2D
    id: str = ""


def dock_from_fields(name: str, fields: Mapping[str, Any], source: str) -> Dock:
    """A Dock from its fields (``type``, ``pose``, optional ``frame`` and ``id``).

    Raises:
        DockDatabaseError: a field is missing or malformed; the message names ``source``, the dock and
            the field.
    """
    where = f"{source}: dock '{name}'"
    kind = fields.get("type")
    if not isinstance(kind, str) or not kind:
        raise DockDatabaseError(f"{where} has no 'type' (the name of one of dock_plugins), got {kind!r}")
    pose = fields.get("pose")
    if (not isinstance(pose, list | tuple) or len(pose) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                       for v in pose)):
        raise DockDatabaseError(f"{where}: 'pose' must be 3 finite numbers [x, y, yaw], got {pose!r}")
    frame = fields.get("frame", DEFAULT_FRAME)
    if not isinstance(frame, str) or not frame.strip("/"):
        raise DockDatabaseError(f"{where}: 'frame' must be a frame name, got {frame!r}")
    dock_id = fields.get("id", "")
    if not isinstance(dock_id, str | int):
        raise DockDatabaseError(f"{where}: 'id' must be a string, got {dock_id!r}")
    return Dock(name, kind, frame.lstrip("/"), Pose2D(*(float(v) for v in pose)), str(dock_id))


def docks_from_yaml(document: Any, source: str) -> dict[str, Dock]:
    """The docks of a parsed dock file (a mapping with a ``docks`` mapping of name → fields)."""
    if not isinstance(document, Mapping) or "docks" not in document:
        raise DockDatabaseError(f"{source}: the dock database does not contain 'docks'")
    entries = document["docks"]
    if not isinstance(entries, Mapping):
        raise DockDatabaseError(f"{source}: 'docks' must map dock names to their fields, got {entries!r}")
    docks = {}
    for name, fields in entries.items():
        if not isinstance(fields, Mapping):
            raise DockDatabaseError(f"{source}: dock '{name}' must be a mapping of fields, got {fields!r}")
        docks[str(name)] = dock_from_fields(str(name), fields, source)
    return docks


def load_dock_file(path: str | Path) -> dict[str, Dock]:
    """The docks of the YAML file at ``path``; DockDatabaseError naming the file when it cannot be used."""
    try:
        text = Path(path).read_text()
    except OSError as error:
        reason = error.strerror or error
        raise DockDatabaseError(f"{path}: cannot read the dock database: {reason}") from error
    try:
        document = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise DockDatabaseError(f"{path}: the dock database is not valid YAML: {error}") from error
    return docks_from_yaml(document, str(path))


class DockDatabase(Generic[P]):
    """Dock instances by name and dock plugins by type name."""

    def __init__(self, plugins: Mapping[str, P], instances: Mapping[str, Dock] | None = None) -> None:
        self.plugins = dict(plugins)
        self.instances = dict(instances or {})

    def reload(self, instances: Mapping[str, Dock]) -> None:
        """Replace every dock instance (plugins stay)."""
        self.instances = dict(instances)

    def find_plugin(self, dock_type: str) -> P | None:
        """The plugin of ``dock_type``; with an empty type, the only plugin if there is exactly one."""
        if not dock_type and len(self.plugins) == 1:
            return next(iter(self.plugins.values()))
        return self.plugins.get(dock_type)

    def find_dock(self, name: str) -> tuple[Dock, P]:
        """The dock instance ``name`` and its plugin.

        Raises:
            DockNotInDB: no instance of that name.
            DockNotValid: the instance's type is not one of the plugins.
        """
        dock = self.instances.get(name)
        if dock is None:
            known = ", ".join(sorted(self.instances)) or "none"
            raise DockNotInDB(f"dock '{name}' is not in the dock database (known docks: {known})")
        plugin = self.find_plugin(dock.type)
        if plugin is None:
            raise DockNotValid(f"dock '{name}' has type '{dock.type}', which is not one of the dock plugins "
                               f"({', '.join(sorted(self.plugins)) or 'none'})")
        return dock, plugin
