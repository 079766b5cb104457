"""The simulator: one robot model in a static world, advanced in fixed physics steps of sim time.

The caller owns time: ``step()`` advances exactly ``physics_step`` seconds; the ROS node decides how
many steps to run per wall second (the real-time factor). Everything random comes from the injected
generator, split into independent streams for the lidar, the odometry and the dock detector, so the
same seed and the same command sequence give identical trajectories and scans, whatever the scan rate.

Docks (sim2d.core.dock): their bodies, shaped for this robot, join the world's obstacles for collisions
and the lidar; the battery charges on their contacts; ``detect_dock()`` reports a seen dock's tag.

Two classes, one code path: :class:`RobotSim` is one robot with its sensors, battery and contacts, fed
its random streams; :class:`Simulator` is the single-robot case, splitting the streams from one seed.
sim2d.core.fleet steps several RobotSims in one world, each an obstacle for the others.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from sim2d.core.battery import Battery, BatteryParams
from sim2d.core.collision import CollisionModel, CollisionParams, Touch
from sim2d.core.disturbances import DroppedObstacle, LidarDropout, OdometrySlip, TopicLoss
from sim2d.core.dock import Dock, dock_in_contact
from sim2d.core.dock_detection import DockDetectionParams, DockDetector, TagDetection
from sim2d.core.geometry import FloatArray, StaticGeometry, normalize_angle
from sim2d.core.lidar import Lidar, LidarParams
from sim2d.core.odometry import Odometry, OdometryParams
from sim2d.core.robot import Pose2D, RobotModel, limit_velocity
from sim2d.core.world import World


@dataclass(frozen=True)
class SimParams:
    """Core simulation settings.

    Attributes:
        physics_step: fixed step (s); kinematics are exact arcs, so it only sets the resolution of
            acceleration limits, contacts and the watchdog.
        cmd_vel_timeout: the robot brakes when no command arrived for this long (s, sim time).
        initial_pose: spawn pose in the map frame (m, rad); also the odom frame's origin.
    """

    physics_step: float = 0.005
    cmd_vel_timeout: float = 0.5
    initial_pose: Pose2D = field(default_factory=lambda: Pose2D(-2.0, -0.5, 0.0))

    def __post_init__(self) -> None:
        if not 0.0 < self.physics_step <= 0.1:
            raise ValueError(f"physics_step: must be in (0, 0.1] s, got {self.physics_step}")
        if self.cmd_vel_timeout <= 0.0:
            raise ValueError(f"cmd_vel_timeout: must be > 0 s, got {self.cmd_vel_timeout}")


@dataclass(frozen=True)
class CollisionEvent:
    """A new contact: sim time (ns), the contact point in the map frame (m), and the robot touched
    (``other``, a fleet robot's name; None for the world: walls, docks, dropped obstacles)."""

    time_ns: int
    x: float
    y: float
    other: str | None = None


@dataclass(frozen=True)
class RobotStreams:
    """One robot's independent random streams: lidar noise, odometry noise, dock detection noise."""

    lidar: np.random.Generator
    odometry: np.random.Generator
    detection: np.random.Generator

    @classmethod
    def spawn(cls, rng: np.random.Generator, robots: int = 1) -> list[RobotStreams]:
        """The streams of ``robots`` robots, three children of ``rng`` each, robot after robot.

        Why this order: the first robot's streams are ``rng``'s children 0, 1, 2, which the single-robot
        simulator has always used (detection third, so the lidar and odometry streams are the same with
        or without docks); so a one-robot fleet repeats a Simulator run with the same seed exactly, and
        adding a robot at the end of a fleet changes no earlier robot's noise.
        """
        children = rng.spawn(3 * robots)
        return [cls(*children[3 * i:3 * i + 3]) for i in range(robots)]


class RobotSim:
    """One robot, its sensors, battery and contacts in a world. Not thread-safe: one caller drives it.

    In a fleet (sim2d.core.fleet) the other robots are named obstacles in :attr:`collision`'s space and
    the ``moving`` geometry of :meth:`scan`; world-level changes (dropped obstacles, teleports) then go
    through the Fleet, which keeps every robot's view of the others current.
    """

    def __init__(self, world: World, robot: RobotModel, params: SimParams, streams: RobotStreams,
                 lidar: LidarParams | None = None, odometry: OdometryParams | None = None,
                 battery: BatteryParams | None = None, collision: CollisionParams | None = None,
                 dock_detection: DockDetectionParams | None = None, name: str = "") -> None:
        """Components left None take their defaults; the lidar takes the robot's own sensor.

        ``name``: the robot's name in a fleet (its namespace), given to the others' collision events.
        """
        self.world, self.robot, self.params, self.name = world, robot, params, name
        bodies = tuple(dock.body(robot) for dock in world.docks)
        geometry = world.geometry.with_polygons(bodies)
        self.lidar = Lidar(lidar or robot.lidar, geometry, streams.lidar)
        self.odometry = Odometry(odometry or OdometryParams(), streams.odometry)
        self.battery = Battery(battery or BatteryParams(), has_docks=bool(world.docks))
        self.collision = CollisionModel(geometry, robot, collision or CollisionParams())
        self.docks: tuple[Dock, ...] = world.docks
        self.docked: Dock | None = None
        self.detector = DockDetector(dock_detection or DockDetectionParams(), world.docks, streams.detection)
        # what can hide dock i's tag: the world and every other dock's body (dropped obstacles join later)
        self._occluders: list[StaticGeometry] = [world.geometry.with_polygons(bodies[:i] + bodies[i + 1:])
                                                 for i in range(len(bodies))]
        self.step_ns = round(params.physics_step * 1e9)
        self.time_ns = 0
        self._timeout_ns = round(params.cmd_vel_timeout * 1e9)
        self.collision_count = 0
        self.collision_events: list[CollisionEvent] = []
        self.dropout = LidarDropout()
        self.slip = OdometrySlip()
        self.topic_loss = TopicLoss()
        self.dropped: list[DroppedObstacle] = []
        self.reset()

    @property
    def time(self) -> float:
        """Sim time (s)."""
        return self.time_ns * 1e-9

    def reset(self) -> None:
        """Robot back to the spawn pose at rest; odometry, battery and collision count restart.

        Sim time keeps running: ROS consumers treat a clock that jumps back as an error. Dropped
        obstacles stay and a lidar dropout runs its course, as models spawned into Gazebo survive
        its reset_world: they are part of the world, not of the robot's state.
        """
        self.pose = self.params.initial_pose
        self.v = self.w = 0.0
        self._command = (0.0, 0.0)
        self._command_ns = self.time_ns - self._timeout_ns - 1
        self.odometry.reset()
        self.battery.reset()
        self.docked = None
        self.collision.in_contact = False
        self.collision_count = 0
        self.collision_events.clear()

    @property
    def command_time_ns(self) -> int:
        """Sim time (ns) of the last command taken; the robot brakes ``cmd_vel_timeout`` after it."""
        return self._command_ns

    def command(self, v: float, w: float) -> None:
        """Set the target body velocity (m/s, rad/s); it holds until ``cmd_vel_timeout`` of sim time."""
        if not (math.isfinite(v) and math.isfinite(w)):
            return
        self._command = (v, w)
        self._command_ns = self.time_ns

    def teleport(self, pose: Pose2D) -> bool:
        """Move the robot (map frame) and stop it; refused (False) if the footprint would overlap.

        Odometry does not notice: a kidnapped robot's wheels did not turn.
        """
        if self.collision.overlaps(pose):
            return False
        self.pose = Pose2D(pose.x, pose.y, normalize_angle(pose.yaw))
        self.v = self.w = 0.0
        self.collision.in_contact = False
        return True

    def drop_obstacle(self, obstacle: DroppedObstacle) -> bool:
        """Add a static circle that the lidar sees and the robot collides with from now on.

        Refused (False) when it would overlap the robot's footprint (sim2d.core.disturbances). In a
        fleet, Fleet.drop_obstacle checks every robot first, then adds the circle to each.
        """
        if not self.collision.add_circle(self.pose, obstacle.x, obstacle.y, obstacle.radius):
            return False
        row = np.array([obstacle.as_row()], dtype=np.float64)
        lidar = self.lidar
        lidar.geometry = replace(lidar.geometry, circles=np.vstack((lidar.geometry.circles, row)))
        self._occluders = [replace(g, circles=np.vstack((g.circles, row))) for g in self._occluders]
        self.dropped.append(obstacle)
        return True

    def drop_lidar(self, duration_s: float) -> None:
        """The lidar returns nothing (+inf on every beam) for ``duration_s`` s of sim time from now."""
        self.dropout.start(self.time_ns, duration_s)

    def slip_odometry(self, scale: float, duration_s: float) -> None:
        """Odometry integrates ``scale`` x the true motion for ``duration_s`` s of sim time from now."""
        self.slip.start(self.time_ns, scale, duration_s)

    def lose_topic(self, topic: str, duration_s: float) -> None:
        """Output ``topic`` (disturbances.LOSABLE_TOPICS) publishes nothing for ``duration_s`` s from now."""
        self.topic_loss.start(topic, self.time_ns, duration_s)

    def step(self) -> Touch | None:
        """Advance one physics step: watchdog, limits, swept motion, contacts, odometry, battery.

        Returns:
            The contact when another robot (a fleet's) stopped this one, so that the fleet can count it
            for that robot too (:meth:`struck`); None otherwise, and always for a robot alone.
        """
        dt = self.params.physics_step
        robot_contact: Touch | None = None
        if self.time_ns - self._command_ns > self._timeout_ns or self.battery.empty:
            target_v = target_w = 0.0
        else:
            target_v, target_w = self._command
        v_new, w_new = limit_velocity(self.robot, self.v, self.w, target_v, target_w, dt)
        v_mean, w_mean = 0.5 * (self.v + v_new), 0.5 * (self.w + w_new)
        distance = 0.0
        blocked = False
        if v_mean != 0.0 or w_mean != 0.0:
            start = self.pose
            result = self.collision.move(start, v_mean, w_mean, dt)
            blocked, end = result.blocked, result.pose
            if blocked:
                v_new = w_new = 0.0
                if not self.collision.in_contact and result.contact is not None:
                    self.collision_events.append(CollisionEvent(self.time_ns + self.step_ns, *result.contact,
                                                                result.other))
                if result.other is not None and result.contact is not None:
                    robot_contact = Touch(result.contact, result.other)
            dx, dy = end.x - start.x, end.y - start.y
            c, s = math.cos(start.yaw), math.sin(start.yaw)
            self.odometry.update(*self.slip.apply(self.time_ns, c * dx + s * dy, -s * dx + c * dy,
                                                  normalize_angle(end.yaw - start.yaw)))
            distance = math.hypot(dx, dy)
            self.pose = end
        if (blocked or self.collision.in_contact) and self.collision.update_contact(self.pose, blocked):
            self.collision_count += 1
        self.v, self.w = v_new, w_new
        self.docked = dock_in_contact(self.docks, self.pose) if self.docks else None
        self.battery.update(self.pose.x, self.pose.y, self.v, self.w, distance, dt, self.docked is not None)
        self.time_ns += self.step_ns
        return robot_contact

    def struck(self, other: str, time_ns: int, point: tuple[float, float]) -> None:
        """Robot ``other`` ran into this one at sim time ``time_ns`` at ``point`` (m, map frame).

        It is this robot's collision too: a new contact unless this robot is already touching
        something, after which the usual hysteresis (:meth:`CollisionModel.update_contact`) ends it.
        """
        if self.collision.in_contact:
            return
        self.collision.in_contact = True
        self.collision_count += 1
        self.collision_events.append(CollisionEvent(time_ns, point[0], point[1], other))

    def scan_pose(self) -> Pose2D:
        """Pose of the scan frame (base_scan, rplidar_link...) in the map frame (m, rad)."""
        ox, oy, _ = self.robot.scan_offset
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        return Pose2D(self.pose.x + c * ox - s * oy, self.pose.y + s * ox + c * oy,
                      normalize_angle(self.pose.yaw + self.robot.scan_yaw))

    def scan(self, moving: StaticGeometry | None = None) -> FloatArray:
        """One lidar scan (beams,) (m, REP 117) taken now; all +inf during a lidar dropout.

        ``moving``: obstacles seen by this scan only, in the map frame (a fleet's other robots).

        The beams are cast even during a dropout, so the lidar's noise stream advances once per scan
        whether the sensor is up or not: a dropout changes the world's randomness only through what
        the robot does about it.
        """
        sensor = self.scan_pose()
        ranges = self.lidar.scan(sensor.x, sensor.y, sensor.yaw, moving)
        if self.dropout.active(self.time_ns):
            ranges[:] = np.inf
        return ranges

    def detect_dock(self) -> TagDetection | None:
        """The tag of the nearest dock the camera sees now, in base_link with noise, or None.

        The noise stream advances only when a tag is reported, so without docks in sight nothing
        else's randomness changes.
        """
        return self.detector.detect(self.pose, self.robot.base_link_z, tuple(self._occluders))

    def pop_collision_events(self) -> list[CollisionEvent]:
        """New contacts since the last call (the node publishes each once)."""
        events, self.collision_events = self.collision_events, []
        return events


class Simulator(RobotSim):
    """One robot alone in a world, its random streams split from one generator (RobotStreams.spawn)."""

    def __init__(self, world: World, robot: RobotModel, params: SimParams, rng: np.random.Generator,
                 lidar: LidarParams | None = None, odometry: OdometryParams | None = None,
                 battery: BatteryParams | None = None, collision: CollisionParams | None = None,
                 dock_detection: DockDetectionParams | None = None) -> None:
        """Components left None take their defaults; the lidar takes the robot's own sensor."""
        (streams,) = RobotStreams.spawn(rng)
        super().__init__(world, robot, params, streams, lidar, odometry, battery, collision, dock_detection)
