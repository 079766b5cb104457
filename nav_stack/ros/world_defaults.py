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
FALLBACK_SPAWN = (-2.0, -0.5, 0.0)  # m, m, rad: turtlebot3_world's spawn, for worlds without spawns


@dataclass(frozen=True)
class WorldDefaults:
    """The map (None: the parameter file's) and spawn (x m, y m, yaw rad) a world implies."""

    map_yaml: Path | None
    spawn: tuple[float, float, float]


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
    spawns = data.get("spawns")
    spawn = FALLBACK_SPAWN
    if isinstance(spawns, list) and spawns and isinstance(spawns[0], list) and len(spawns[0]) == 3:
        spawn = (float(spawns[0][0]), float(spawns[0][1]), float(spawns[0][2]))
    map_yaml = MAPS_DIR / f"{path.stem}.yaml"
    return WorldDefaults(map_yaml if map_yaml.is_file() else None, spawn)
