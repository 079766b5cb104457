"""The node's parameters: one flat ROS namespace built from the core's frozen dataclasses.

Why here and without rclpy: the CLI validates a parameter file and its flags before starting ROS,
so a bad value fails at once with a one-line error naming the file and key; the node declares
the same names with the same defaults (the dataclass defaults are the only source of truth).

Layout (Nav2 style, config/sim2d.yaml)::

    sim2d:
      ros__parameters:
        world: turtlebot3_world      # NodeParams and SimParams fields at the top level
        initial_pose: {x: -2.0, y: -0.5, yaw: 0.0}
        lidar: {beams: 360, ...}     # LidarParams, OdometryParams, BatteryParams, CollisionParams
        lockstep: {enabled: false, participants: [nav2]}   # LockstepParams (string arrays are tuples)
        dock_detection: {rate: 10.0, fov: 1.25, ...}       # DockDetectionParams
        fleet: ["robot1:waffle:-2.0,-0.5,0.0", "robot2:tb4:0.5,2.0,3.14"]   # several robots (below)

The lidar's defaults are the robot's sensor (sim2d/core/robot.py: LDS-01 on the TurtleBot3s, RPLIDAR
A1 on tb4), applied under the user's values: an explicit ``lidar.*`` (file, ``-p``) still wins.

A fleet (issue 48) is the string array ``fleet``, one ``name:model:x,y,yaw`` per robot (yaw may be
left out: 0). Why a string array rather than a list of mappings or a separate fleet file: ROS 2
parameters have no nested lists, so a list of ``{name, model, spawn}`` mappings cannot be declared;
a string array is one native parameter that ``-p fleet:=[...]``, a launch file and ``ros2 param get``
all handle, and it keeps the whole simulator in one parameter file. Empty (the default) is one robot
(``robot``, ``initial_pose``) on the un-namespaced topics. With a fleet, ``robot`` and
``initial_pose`` are not used, except that ``lidar.*`` values that differ from ``robot``'s sensor
apply to every robot's own sensor (:func:`fleet_robots`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from sim2d.core.battery import BatteryParams
from sim2d.core.collision import CollisionParams
from sim2d.core.dock_detection import DockDetectionParams
from sim2d.core.fleet import FleetRobot
from sim2d.core.lidar import LidarParams
from sim2d.core.odometry import OdometryParams
from sim2d.core.robot import Pose2D, robot_model
from sim2d.core.simulator import SimParams

NODE_NAME = "sim2d"
ParamValue = bool | int | float | str | tuple[str, ...]


@dataclass(frozen=True)
class NodeParams:
    """ROS-side settings.

    Attributes:
        world: world name (sim2d/worlds/<name>.yaml) or path to a world or map_server YAML.
        robot: a model of sim2d.core.robot.ROBOTS: "waffle", "burger" or "tb4".
        seed: seed of every random stream (lidar noise, odometry drift).
        real_time_factor: sim seconds per wall second; 0 runs as fast as possible.
        enable_stamped_cmd_vel: cmd_vel is TwistStamped instead of Twist (Nav2's knob).
        stamped_cmd_vel_delay: s of sim time after its stamp that a TwistStamped command takes effect
            (sim2d/core/command_schedule.py: the same effect at the same sim time on every run);
            0, or a zero stamp, applies it on arrival, as a Twist always is. In lockstep keep it
            above ``lockstep.max_lead`` plus one report period, or commands arrive late.
        clock_rate: /clock messages per sim second (Hz); sets the resolution of sim-time timers.
        battery_rate: /battery_state messages per sim second (Hz).
        rtf_log_period: wall seconds between log lines reporting the achieved real-time factor.
        fleet: the robots of a fleet, ``name:model:x,y,yaw`` each (m, m, rad in the map frame;
            :func:`parse_fleet`); each robot's topics and TF live under ``/<name>``. Empty: one
            robot, ``robot`` at ``initial_pose``, on the un-namespaced topics.
    """

    world: str = "turtlebot3_world"
    robot: str = "waffle"
    seed: int = 0
    real_time_factor: float = 1.0
    enable_stamped_cmd_vel: bool = False
    stamped_cmd_vel_delay: float = 0.1
    clock_rate: float = 100.0
    battery_rate: float = 1.0
    rtf_log_period: float = 10.0
    fleet: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.real_time_factor < 0.0:
            raise ValueError(f"real_time_factor: must be > 0 (or 0 = max speed), got {self.real_time_factor}")
        if self.stamped_cmd_vel_delay < 0.0:
            raise ValueError(f"stamped_cmd_vel_delay: must be >= 0 s, got {self.stamped_cmd_vel_delay}")
        for name in ("clock_rate", "battery_rate", "rtf_log_period"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"{name}: must be > 0, got {getattr(self, name)}")
        parse_fleet(self.fleet)   # a bad entry fails with the parameters, before anything starts


@dataclass(frozen=True)
class LockstepParams:
    """Lockstep with the stack (see sim2d/core/lockstep.py and ros_tools/runtime/lockstep.py).

    Attributes:
        enabled: never step more than ``max_lead`` beyond the slowest participant's report.
        max_lead: s of sim time the sim may run ahead of the slowest participant (one control
            period of a 20 Hz controller); at least one physics step, or the sim could never step.
        timeout: wall seconds without a report after which a live participant is dropped (one
            warning); one whose process is gone is dropped after 1 s (sim2d/core/lockstep.py).
        startup_timeout: wall seconds to wait for the ``participants`` roles before the first step.
        participants: roles (``nav2``, ``localization``...) that must report before the sim steps;
            a fleet's stacks report as ``<robot>/<role>`` (``robot1/nav2``): any text without ':'
            is a role, since ':' separates the role from the pid in a participant's name.
    """

    enabled: bool = False
    max_lead: float = 0.05
    timeout: float = 10.0
    startup_timeout: float = 60.0
    participants: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in ("max_lead", "timeout", "startup_timeout"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"lockstep.{name}: must be > 0, got {getattr(self, name)}")
        for role in self.participants:
            if not role.strip() or ":" in role:
                raise ValueError(f"lockstep.participants: a role is a name without ':', got {role!r}")


@dataclass(frozen=True)
class SimConfig:
    """Everything the node needs, validated."""

    node: NodeParams
    sim: SimParams
    lidar: LidarParams
    odometry: OdometryParams
    battery: BatteryParams
    collision: CollisionParams
    lockstep: LockstepParams
    dock_detection: DockDetectionParams

    def __post_init__(self) -> None:
        if self.lockstep.max_lead < self.sim.physics_step:
            raise ValueError(f"lockstep.max_lead: must be at least physics_step ({self.sim.physics_step} s), "
                             f"got {self.lockstep.max_lead}")


def parse_fleet(entries: Sequence[str]) -> tuple[FleetRobot, ...]:
    """The robots of a ``fleet`` parameter, in its order (which is also the fleet's step order).

    Each entry is ``name:model:x,y,yaw`` (yaw optional, 0): ``robot1:waffle:-2.0,-0.5,0.0``. Names and
    spawns are checked by FleetRobot (a ROS 2 name token, finite numbers); a repeated name or a spawn
    on an obstacle needs the world and fails when the node builds the fleet (check_fleet).

    Raises:
        ValueError: naming the parameter and the entry, and what is wrong with it.
    """
    robots = []
    for entry in entries:
        where = f"fleet: entry {entry!r}"
        parts = [part.strip() for part in entry.split(":")]
        numbers = parts[2].split(",") if len(parts) == 3 else []
        if len(numbers) not in (2, 3):
            raise ValueError(f"{where}: expected 'name:model:x,y,yaw' (m, m, rad; yaw optional), "
                             "e.g. 'robot1:waffle:-2.0,-0.5,0.0'")
        try:
            pose = Pose2D(*(float(number) for number in numbers))
            robots.append(FleetRobot(parts[0], robot_model(parts[1]), pose))
        except ValueError as exc:
            raise ValueError(f"{where}: {str(exc).removeprefix('fleet: ')}") from exc
    return tuple(robots)


_ROOTS: tuple[type, ...] = (NodeParams, SimParams)
_SECTIONS: dict[str, type] = {"lidar": LidarParams, "odometry": OdometryParams, "battery": BatteryParams,
                              "collision": CollisionParams, "lockstep": LockstepParams,
                              "dock_detection": DockDetectionParams}


def _default(f: dataclasses.Field[Any]) -> Any:
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return f.default


def _flatten_defaults(instance: Any, prefix: str, out: dict[str, ParamValue]) -> None:
    for f in dataclasses.fields(instance):
        value = getattr(instance, f.name)
        if dataclasses.is_dataclass(value):
            _flatten_defaults(value, f"{prefix}{f.name}.", out)
        elif isinstance(value, tuple) and not all(isinstance(item, str) for item in value):
            continue  # not a parameter (only string tuples are: ROS string arrays)
        else:
            out[f"{prefix}{f.name}"] = value


def defaults(robot: str = NodeParams.robot) -> dict[str, ParamValue]:
    """Every parameter name (dotted) and its default for ``robot``: the lidar's are its sensor's.

    Names and types do not depend on the robot, only the lidar's values do. ValueError for an
    unknown robot.
    """
    out: dict[str, ParamValue] = {}
    for cls in _ROOTS:
        _flatten_defaults(cls(), "", out)
    sections = {section: cls() for section, cls in _SECTIONS.items()}
    sections["lidar"] = robot_model(robot).lidar
    for section, instance in sections.items():
        _flatten_defaults(instance, f"{section}.", out)
    return out


def declare_all(declare: Callable[[str, ParamValue], Any]) -> dict[str, ParamValue]:
    """Every parameter's value, each obtained once through ``declare(name, default)`` (the node's
    declare_parameter): ``robot`` first, since the other defaults depend on it."""
    robot = str(coerce("robot", declare("robot", NodeParams.robot)))
    values: dict[str, ParamValue] = {"robot": robot}
    for name, default in defaults(robot).items():
        if name != "robot":
            values[name] = coerce(name, declare(name, default))
    return values


def coerce(name: str, value: Any, where: str = "") -> ParamValue:
    """``value`` converted to the type of ``name``'s default; ValueError names ``where`` and key."""
    known = defaults()
    prefix = f"{where}: " if where else ""
    if name not in known:
        raise ValueError(f"{prefix}{name}: unknown parameter")
    default = known[name]
    if isinstance(default, tuple):   # a string array; rclpy types an empty default as a byte array
        ok = isinstance(value, (list, tuple)) and all(isinstance(item, str) for item in value)
        ok = ok or (not isinstance(value, str) and hasattr(value, "__len__") and len(value) == 0)
        value = tuple(value) if ok else value
    elif isinstance(default, bool):
        ok = isinstance(value, bool)
    elif isinstance(default, float):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        value = float(value) if ok else value
    elif isinstance(default, int):
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, str)
    if not ok:
        expected = "list of str" if isinstance(default, tuple) else type(default).__name__
        raise ValueError(f"{prefix}{name}: expected {expected}, got {value!r}")
    return value  # type: ignore[no-any-return]


def _build(cls: type, prefix: str, values: dict[str, ParamValue]) -> Any:
    kwargs: dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        name = f"{prefix}{f.name}"
        nested = _default(f)
        if dataclasses.is_dataclass(nested):
            kwargs[f.name] = _build(type(nested), f"{name}.", values)
        elif name in values:
            kwargs[f.name] = values[name]
    return cls(**kwargs)


def build_config(values: dict[str, ParamValue]) -> SimConfig:
    """A validated SimConfig from dotted parameter values (missing ones take the robot's defaults)."""
    merged = {**defaults(str(values.get("robot", NodeParams.robot))), **values}
    return SimConfig(_build(NodeParams, "", merged), _build(SimParams, "", merged),
                     *(_build(cls, f"{section}.", merged) for section, cls in _SECTIONS.items()))


def fleet_robots(config: SimConfig) -> tuple[FleetRobot, ...]:
    """The declared fleet, each robot with its own model's lidar under the user's ``lidar.*`` values.

    Why: the lidar parameters default to ``robot``'s sensor (:func:`defaults`), one model for the whole
    node, while a fleet mixes models. A ``lidar.*`` value that differs from ``robot``'s sensor was set
    by the user and applies to every robot; the others keep each model's own figures (a value set
    equal to ``robot``'s default cannot be told apart, and leaves the other models' figures).
    """
    reference = robot_model(config.node.robot).lidar
    overrides = {f.name: getattr(config.lidar, f.name) for f in dataclasses.fields(LidarParams)
                 if getattr(config.lidar, f.name) != getattr(reference, f.name)}
    robots = parse_fleet(config.node.fleet)
    if not overrides:
        return robots
    return tuple(dataclasses.replace(robot, model=dataclasses.replace(
        robot.model, lidar=dataclasses.replace(robot.model.lidar, **overrides))) for robot in robots)


def load_params_file(path: str | Path) -> dict[str, ParamValue]:
    """Dotted parameters from a Nav2-style file (``sim2d: ros__parameters:``; ``/**`` also read)."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ValueError(f"{path}: cannot read parameter file ({exc})") from exc
    if not isinstance(data, dict):
        raise ValueError(f"{path}: expected '{NODE_NAME}: ros__parameters:' at the top level")
    values: dict[str, ParamValue] = {}
    for node_key in ("/**", NODE_NAME, f"/{NODE_NAME}"):
        section = data.get(node_key)
        if section is None:
            continue
        params = section.get("ros__parameters") if isinstance(section, dict) else None
        if not isinstance(params, dict):
            raise ValueError(f"{path}: {node_key}.ros__parameters: missing or not a mapping")
        _flatten_yaml(params, "", values, f"{path}: {node_key}.ros__parameters", node_key == "/**")
    return values


def _flatten_yaml(node: dict[str, Any], prefix: str, out: dict[str, ParamValue], where: str,
                  lenient: bool) -> None:
    known = defaults()
    for key, value in node.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            _flatten_yaml(value, f"{name}.", out, where, lenient)
        elif lenient and name not in known:
            continue  # '/**' sections carry other nodes' parameters (use_sim_time, ...)
        elif name != "use_sim_time":
            out[name] = coerce(name, value, where)
