"""What ``nav-bringup --world NAME`` implies when the user did not say: the world's map and spawn.

Why: a world comes with its map (maps/NAME.yaml, generated from the world file) and its spawn
poses (the world file's ``spawns``, the first being the default). Without these defaults
``--world turtlebot3_house`` would localize the house on turtlebot3_world's map at that world's
spawn, and AMCL would be lost from the first scan.

The world file is read as data (YAML) from the shipped data (navsuite_data), like a launch file
reads another package's share folder: nav_stack never imports sim2d. Explicit ``--map`` and
``--x/--y/--yaw`` always win.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import yaml

from navsuite_data import data_dir, resolve

WORLDS_DIR = data_dir("worlds")
MAPS_DIR = data_dir("maps")
Pose = tuple[float, float, float]  # x m, y m, yaw rad (map frame)
FALLBACK_SPAWN: Pose = (-2.0, -0.5, 0.0)  # turtlebot3_world's spawn, for worlds without spawns


@dataclass(frozen=True)
class WorldDefaults:
    """The map (None: the parameter file's) and spawn (x m, y m, yaw rad) a world implies, and every
    spawn the world file lists, in order (a fleet's robots take them one by one:
    nav_stack.core.fleet_spawns)."""

    map_yaml: Path | None
    spawn: Pose
    spawns: tuple[Pose, ...] = ()


def world_defaults(world: str) -> WorldDefaults:
    """Defaults for a world given by name (a shipped world, sim2d/worlds/NAME.yaml) or path (world or
    map YAML; relative to the working directory, else a shipped file of that name).

    A map_server YAML used as a world is its own map; a world file's map is maps/<stem>.yaml when
    it exists. The spawn is the world file's first ``spawns`` entry, else FALLBACK_SPAWN.
    """
    path = resolve(world) if world.endswith((".yaml", ".yml")) else WORLDS_DIR / f"{world}.yaml"
    try:
        data = yaml.safe_load(path.read_text()) if path.is_file() else None
    except (OSError, yaml.YAMLError):
        data = None  # sim2d reports a broken world file with its own message
    if not isinstance(data, dict):
        return WorldDefaults(None, FALLBACK_SPAWN)
    if "image" in data:
        return WorldDefaults(path.resolve(), FALLBACK_SPAWN)
    spawns = _spawns(data.get("spawns"))
    map_yaml = MAPS_DIR / f"{path.stem}.yaml"
    return WorldDefaults(map_yaml if map_yaml.is_file() else None, spawns[0] if spawns else FALLBACK_SPAWN,
                         spawns)


def _spawns(listed: object) -> tuple[Pose, ...]:
    """The world file's ``spawns`` up to the first entry that is not three numbers (sim2d refuses a
    broken world file with its own message)."""
    poses: list[Pose] = []
    for entry in listed if isinstance(listed, list) else []:
        if not (isinstance(entry, list) and len(entry) == 3
                and all(isinstance(v, int | float) and not isinstance(v, bool) for v in entry)):
            break
        poses.append((float(entry[0]), float(entry[1]), float(entry[2])))
    return tuple(poses)
