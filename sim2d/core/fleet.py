"""A fleet: several robots in one world, stepped together, each an obstacle for the others.

Why a fleet in the core: warehouse state machines coordinate robots (a shared corridor, one charger),
so the simulator must make robots meet the way bodies do: they see each other in their lidars, they
cannot drive through each other, and a robot-robot contact is a collision for both (issue 48).

How: each robot is a :class:`~sim2d.core.simulator.RobotSim`, the same code a lone Simulator runs,
with its own model, random streams, odometry, battery and contacts. On top of its static world:

* collisions: every other robot is a named kinematic body in the robot's pymunk space, carrying that
  robot's footprint (the polygon it collides with itself). A robot stopped by another records an
  event naming it, and the other records one naming the first (RobotSim.struck), each counted once
  by the usual contact hysteresis. Before a robot moves, the bodies within :data:`REACH_SLACK` of
  its reach (where they stand, or where its space last put them) are moved to where they stand; the
  others cannot be met in one step and stay where they were last put. Why: pymunk re-indexes a moved
  body (about 5 µs), and doing it for every pair at every step nearly doubled a step's cost;
* lidar: each scan also casts against the other robots' bodies where they stand now: circles for
  round bases (the TB4's Create 3), footprint polygons for box-shaped ones (TB3 waffle, burger).

Order within a step: robots move one after the other, in declaration order, each against the others'
latest poses (the earlier ones have already moved this step). Two robots can therefore never claim
the same free space in one step, and the outcome depends only on the seed, the commands and the
order. Robot i's noise comes from the fleet generator's children 3i..3i+2 (RobotStreams.spawn): a
one-robot fleet repeats a Simulator with the same seed bit for bit, and adding a robot at the end
changes no earlier robot's noise.

Not modelled yet: other robots hiding a dock's tag from the camera (RobotSim.detect_dock sees the
world and the docks only), and a dock body is shaped for the robot that meets it, so two models see
slightly different bodies of the same dock (sim2d.core.dock).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from sim2d.core.battery import BatteryParams
from sim2d.core.clearance import placed_footprint
from sim2d.core.collision import CollisionParams
from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.dock_detection import DockDetectionParams
from sim2d.core.geometry import FloatArray, StaticGeometry, polygon_edges
from sim2d.core.lidar import LidarParams
from sim2d.core.odometry import OdometryParams
from sim2d.core.robot import Pose2D, RobotModel
from sim2d.core.simulator import RobotSim, RobotStreams, SimParams
from sim2d.core.world import World, check_spawn

#: A ROS 2 name token (design.ros2.org, topic and service names): letters, digits and underscores, not
#: starting with a digit, no repeated underscores. A robot's name becomes its namespace (/robot1/scan).
_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

#: m beyond two robots' combined bounding radii within which their bodies are kept current in each
#: other's collision space; far more than a robot travels in one physics step (0.3 m/s x 0.1 s).
REACH_SLACK = 0.5


def _pose_text(pose: Pose2D) -> str:
    return f"({pose.x:g}, {pose.y:g}, {pose.yaw:g})"


@dataclass(frozen=True)
class FleetRobot:
    """One robot of a fleet declaration.

    Attributes:
        name: a ROS 2 name token (robot1, tb4_a...): the robot's namespace in the ROS layer.
        model: the robot model (sim2d.core.robot.ROBOTS); models may be mixed in a fleet.
        spawn: the start pose in the map frame (m, rad); also that robot's odom origin.
    """

    name: str
    model: RobotModel
    spawn: Pose2D

    def __post_init__(self) -> None:
        if not _TOKEN.fullmatch(self.name) or "__" in self.name:
            raise ValueError(f"fleet: robot name {self.name!r} is not a valid ROS 2 namespace token "
                             "(letters, digits and single underscores, not starting with a digit: robot1)")
        if not all(math.isfinite(v) for v in (self.spawn.x, self.spawn.y, self.spawn.yaw)):
            raise ValueError(f"fleet: robot {self.name!r}: spawn {_pose_text(self.spawn)} must be finite")


def check_fleet(world: World, robots: Sequence[FleetRobot]) -> None:
    """Refuse an empty fleet, a repeated name, or a spawn that touches the world's obstacles.

    Why apart from the Fleet: a launcher can check a fleet file before it starts anything. Overlaps
    between robots are checked by the Fleet, with the footprints it collides (:class:`Fleet`).

    Raises:
        ValueError: naming the robot and its spawn pose.
    """
    if not robots:
        raise ValueError("fleet: declare at least one robot (name, model, spawn)")
    seen: set[str] = set()
    for robot in robots:
        if robot.name in seen:
            raise ValueError(f"fleet: robot name {robot.name!r} is declared twice; names must be unique")
        seen.add(robot.name)
        try:
            check_spawn(world, robot.spawn.x, robot.spawn.y, robot.model.bounding_radius())
        except ValueError as exc:
            raise ValueError(f"fleet: robot {robot.name!r}: {exc}") from exc


def body_geometry(robots: Sequence[RobotSim]) -> StaticGeometry:
    """The bodies of ``robots`` at their current poses, as the lidar sees them (m, map frame).

    A round base is its circle (centred ``footprint_offset_x`` ahead of base_footprint), a box-shaped
    base the footprint polygon it collides with.
    """
    circles: list[list[float]] = []
    polygons: list[FloatArray] = []
    for sim in robots:
        model, pose = sim.robot, sim.pose
        if model.footprint_radius > 0.0:
            offset = model.footprint_offset_x
            circles.append([pose.x + offset * math.cos(pose.yaw), pose.y + offset * math.sin(pose.yaw),
                            model.footprint_radius])
        else:
            polygons.append(placed_footprint(model, pose))
    # the edges given, not left to StaticGeometry: it would add its (empty) boxes' edges, a third of the cost
    edges = np.concatenate([polygon_edges(p) for p in polygons]) if polygons else np.zeros((0, 4))
    return StaticGeometry(circles=np.array(circles, dtype=np.float64).reshape(-1, 3),
                          polygons=tuple(polygons), segments=edges)


class Fleet:
    """Robots in one world under one clock. Not thread-safe: one caller drives it.

    ``robots`` maps each name to its RobotSim, in declaration order: command a robot, read its pose,
    odometry, battery and collision events there. Change the world or a pose through the fleet
    (:meth:`drop_obstacle`, :meth:`teleport`, :meth:`reset`), which keeps every robot's view of the
    others current, and scan through :meth:`scan`, which adds the other robots.
    """

    def __init__(self, world: World, robots: Sequence[FleetRobot], params: SimParams,
                 rng: np.random.Generator, lidar: LidarParams | None = None,
                 odometry: OdometryParams | None = None,
                 battery: BatteryParams | None = None, collision: CollisionParams | None = None,
                 dock_detection: DockDetectionParams | None = None) -> None:
        """``params`` apply to every robot except ``initial_pose`` (each robot's spawn replaces it);
        components left None take their defaults (the lidar: each model's own sensor).

        Raises:
            ValueError: a bad declaration (:func:`check_fleet`) or two spawns whose footprints overlap.
        """
        check_fleet(world, robots)
        streams = RobotStreams.spawn(rng, len(robots))
        self.world, self.params = world, params
        self.robots: dict[str, RobotSim] = {
            robot.name: RobotSim(world, robot.model, replace(params, initial_pose=robot.spawn), stream, lidar,
                                 odometry, battery, collision, dock_detection, name=robot.name)
            for robot, stream in zip(robots, streams, strict=True)}
        for sim in self.robots.values():
            for other in self._others(sim.name):
                sim.collision.add_robot(other.name, other.robot, other.pose)
        for sim in reversed(self.robots.values()):   # the last one first: an overlap names the later robot
            touch = sim.collision.touching(sim.pose)
            if touch is not None:
                what = (f"robot {touch.other!r} at {_pose_text(self.robots[touch.other].pose)}" if touch.other
                        else f"an obstacle (a dock's body?) at ({touch.point[0]:.3f}, {touch.point[1]:.3f})")
                raise ValueError(f"fleet: robot {sim.name!r}: spawn {_pose_text(sim.pose)} overlaps {what}; "
                                 f"spawn the robots apart")
        # where robot k's collision space shows each other robot j, and the distance (m) within which
        # that must be where j stands
        self._shown = {sim.name: {other.name: other.pose for other in self._others(sim.name)}
                       for sim in self.robots.values()}
        self._reach = {(sim.name, other.name): sim.robot.bounding_radius() + other.robot.bounding_radius()
                       + REACH_SLACK for sim in self.robots.values() for other in self._others(sim.name)}
        self.step_ns = round(params.physics_step * 1e9)
        self.time_ns = 0

    @property
    def time(self) -> float:
        """Sim time (s)."""
        return self.time_ns * 1e-9

    def robot(self, name: str) -> RobotSim:
        """The robot called ``name``; a ValueError lists the fleet's names."""
        if name not in self.robots:
            raise ValueError(f"fleet: no robot {name!r} (robots: {', '.join(self.robots)})")
        return self.robots[name]

    def _others(self, name: str) -> list[RobotSim]:
        return [sim for other, sim in self.robots.items() if other != name]

    def _refresh(self, sim: RobotSim, everyone: bool = False) -> None:
        """Move the other robots' bodies in ``sim``'s collision space to where they stand: those within
        reach of ``sim`` where they stand or where they are shown (the module doc), or ``everyone``."""
        shown = self._shown[sim.name]
        here = sim.pose
        for other in self._others(sim.name):
            seen, there = shown[other.name], other.pose
            if seen is there:   # poses are replaced, never mutated: the same object is the same place
                continue
            reach = self._reach[sim.name, other.name]
            if (everyone or math.hypot(there.x - here.x, there.y - here.y) < reach
                    or math.hypot(seen.x - here.x, seen.y - here.y) < reach):
                sim.collision.place_robot(other.name, there)
                shown[other.name] = there

    def step(self) -> None:
        """Advance every robot one physics step, in declaration order (see the module doc)."""
        for sim in self.robots.values():
            self._refresh(sim)
            touch = sim.step()
            if touch is not None and touch.other is not None:
                self.robots[touch.other].struck(sim.name, sim.time_ns, touch.point)
        self.time_ns += self.step_ns

    def scan(self, name: str) -> FloatArray:
        """Robot ``name``'s lidar scan now (RobotSim.scan), the other robots' bodies included."""
        sim = self.robot(name)
        others = self._others(name)
        return sim.scan(body_geometry(others) if others else None)

    def teleport(self, name: str, pose: Pose2D) -> bool:
        """Move robot ``name`` to ``pose`` and stop it; refused (False) onto an obstacle or a robot."""
        sim = self.robot(name)
        self._refresh(sim, everyone=True)       # the target may be anywhere
        return sim.teleport(pose)

    def drop_obstacle(self, obstacle: DroppedObstacle) -> bool:
        """Add a static circle that every robot sees and collides with; refused (False) when it would
        overlap any robot's footprint."""
        sims = list(self.robots.values())
        if any(s.collision.circle_overlaps(s.pose, obstacle.x, obstacle.y, obstacle.radius) for s in sims):
            return False
        return all([sim.drop_obstacle(obstacle) for sim in sims])

    def reset(self) -> None:
        """Every robot back to its spawn at rest (RobotSim.reset); sim time keeps running."""
        for sim in self.robots.values():
            sim.reset()

