"""Which robots a fleet launch runs: names, models and spawn poses, from a fleet file or a count.

Why in the core: ``nav-bringup --fleet FILE`` must refuse a bad file before it starts a single
process, with one message naming the file, the robot and the key, and ``--robots N`` must pick N
spawn poses that a simulator accepts. Both are plain data work, tested without ROS.

A fleet file is a YAML list (or a mapping with a ``robots:`` list) of::

    - {name: robot1, model: waffle, x: -2.0, y: -0.5, yaw: 0.0}   # m, m, rad in the map frame

``model`` defaults to the launch's ``--robot`` and ``yaw`` to 0. A robot's name becomes its ROS
namespace (``/robot1``), so it must be a ROS 2 name token. The names of the robot models are the
caller's (nav_stack/ros/bringup/robot_params.py restates sim2d's), since the core imports neither.
Geometry against the world (a spawn inside a wall, two robots overlapping) is the simulator's to
refuse: it knows the exact shapes.

Pure: yaml and the standard library only.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

#: A ROS 2 name token (letters, digits, underscores; not starting with a digit; no "__"): the same
#: rule sim2d applies to its fleet, restated because nav_stack never imports sim2d.
NAME_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: The keys of one robot in a fleet file.
KEYS = ("name", "model", "x", "y", "yaw")


class FleetSpecError(ValueError):
    """A fleet declaration that cannot run (the message names the file, the robot and the key)."""


@dataclass(frozen=True)
class FleetMember:
    """One robot of a fleet launch.

    Attributes:
        name: its ROS namespace without slashes (``robot1``).
        model: the simulated robot model (``waffle``, ``burger``, ``tb4``).
        x: spawn x in the map frame (m); also where its initial pose is published.
        y: spawn y in the map frame (m).
        yaw: spawn heading in the map frame (rad).
    """

    name: str
    model: str
    x: float
    y: float
    yaw: float = 0.0

    def __post_init__(self) -> None:
        check_robot_name(self.name)
        if not all(math.isfinite(v) for v in (self.x, self.y, self.yaw)):
            raise FleetSpecError(f"robot {self.name!r}: spawn ({self.x}, {self.y}, {self.yaw}) "
                                 "must be finite")

    @property
    def pose(self) -> tuple[float, float, float]:
        """The spawn (x m, y m, yaw rad)."""
        return self.x, self.y, self.yaw


def check_robot_name(name: str) -> None:
    """Refuse a robot name that is not a ROS 2 name token (it becomes the robot's namespace)."""
    if not NAME_TOKEN.fullmatch(name) or "__" in name:
        raise FleetSpecError(f"robot name {name!r} is not a valid ROS 2 namespace token (letters, digits and "
                             "single underscores, not starting with a digit: robot1)")


def check_fleet(members: Sequence[FleetMember], models: Sequence[str]) -> None:
    """Refuse an empty fleet, a name given twice or a model the stack has no parameters for."""
    if not members:
        raise FleetSpecError("a fleet needs at least one robot")
    seen: set[str] = set()
    for member in members:
        if member.name in seen:
            raise FleetSpecError(f"robot name {member.name!r} is declared twice; names must be unique")
        seen.add(member.name)
        if member.model not in models:
            raise FleetSpecError(f"robot {member.name!r}: unknown model {member.model!r} "
                                 f"(known: {', '.join(models)})")


def _number(path: Path, where: str, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise FleetSpecError(f"{path}: {where}: {key}: expected a number, got {value!r}")
    return float(value)


def _member(path: Path, index: int, item: Any, default_model: str) -> FleetMember:
    where = f"robot {index}"
    if not isinstance(item, dict):
        raise FleetSpecError(f"{path}: {where}: expected a mapping with {', '.join(KEYS)}, got {item!r}")
    unknown = sorted(str(key) for key in item if key not in KEYS)
    if unknown:
        raise FleetSpecError(f"{path}: {where}: unknown key(s) {', '.join(unknown)} "
                             f"(known: {', '.join(KEYS)})")
    missing = [key for key in ("name", "x", "y") if key not in item]
    if missing:
        raise FleetSpecError(f"{path}: {where}: missing {', '.join(missing)}")
    name, model = item["name"], item.get("model", default_model)
    if not isinstance(name, str) or not isinstance(model, str):
        raise FleetSpecError(f"{path}: {where}: name and model must be strings, got {name!r}, {model!r}")
    try:
        x, y, yaw = (_number(path, where, key, item.get(key, 0.0)) for key in ("x", "y", "yaw"))
        return FleetMember(name, model, x, y, yaw)
    except FleetSpecError as error:
        raise FleetSpecError(f"{path}: {where}: {error}") from None


def load_fleet_file(path: Path, models: Sequence[str], default_model: str) -> tuple[FleetMember, ...]:
    """The robots of a fleet file, checked (:func:`check_fleet`); FleetSpecError names the file."""
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as error:
        raise FleetSpecError(f"{path}: cannot read it: {error.strerror or error}") from error
    except yaml.YAMLError as error:
        raise FleetSpecError(f"{path}: not valid YAML: {error}") from error
    if isinstance(data, dict) and set(data) == {"robots"}:
        data = data["robots"]
    if not isinstance(data, list):
        raise FleetSpecError(f"{path}: expected a list of robots ({', '.join(KEYS)}) or a 'robots:' key")
    members = tuple(_member(path, index, item, default_model) for index, item in enumerate(data))
    try:
        check_fleet(members, models)
    except FleetSpecError as error:
        raise FleetSpecError(f"{path}: {error}") from None
    return members


def numbered_fleet(model: str, spawns: Sequence[tuple[float, float, float]]) -> tuple[FleetMember, ...]:
    """``robot1`` .. ``robotN`` of one model at ``spawns`` (x m, y m, yaw rad each), Nav2's names."""
    return tuple(FleetMember(f"robot{i + 1}", model, *pose) for i, pose in enumerate(spawns))


def sim_fleet_entries(members: Sequence[FleetMember]) -> list[str]:
    """sim2d's ``fleet`` parameter: ``name:model:x,y,yaw`` per robot (repr keeps every digit)."""
    return [f"{m.name}:{m.model}:{m.x!r},{m.y!r},{m.yaw!r}" for m in members]
