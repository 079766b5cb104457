"""The topics that act on sim2d's world from outside: teleport, lidar dropout, dropped obstacles.

Why topics with standard messages (like Gazebo's set_entity_state / spawn_entity, but with no custom
interface): ``ros2 topic pub`` and any Nav2 test harness can drive them, and a scenario's injector
can publish them at a sim time. Each takes effect at the sim time it arrives: under lockstep the
sender is a participant, so that is within one lockstep lead (0.05 s) of the /clock it acted on.

  sub  sim2d/teleport (geometry_msgs/PoseStamped, frame map): move the robot; odometry does not notice
  sub  sim2d/lidar_dropout (std_msgs/Float64): every beam reads +inf (REP 117: no return) for
       ``data`` s of sim time; <= 0 brings the lidar back at once (sim2d.core.disturbances says why
       +inf rather than silence)
  sub  sim2d/spawn_obstacle (visualization_msgs/Marker, type CYLINDER, action ADD, frame map):
       a static round obstacle of radius scale.x / 2 m at pose.position, seen by the lidar and
       collided with; refused with a warning when it would overlap the robot

In a fleet (issue 48) teleport and lidar_dropout are each robot's, under its namespace
(/robot1/sim2d/teleport), and spawn_obstacle stays un-namespaced: the obstacle is in the world every
robot shares (:class:`FleetMember` routes them through the Fleet, which keeps every robot's view of
the others current).

The callbacks only translate and log; the core (``Simulator.teleport``, ``drop_lidar``,
``drop_obstacle``, or the Fleet's) holds the logic and the checks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_msgs.msg import Float64
from visualization_msgs.msg import Marker

from ros_tools.geometry import yaw_of
from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.fleet import Fleet
from sim2d.core.robot import Pose2D
from sim2d.ros import messages

TELEPORT_TOPIC = "sim2d/teleport"
LIDAR_DROPOUT_TOPIC = "sim2d/lidar_dropout"
SPAWN_OBSTACLE_TOPIC = "sim2d/spawn_obstacle"
ROBOT_TOPICS = (TELEPORT_TOPIC, LIDAR_DROPOUT_TOPIC)   # one robot's (namespaced in a fleet)
ALL_TOPICS = (*ROBOT_TOPICS, SPAWN_OBSTACLE_TOPIC)


class WorldTarget(Protocol):
    """What the inputs act on: a Simulator, or one robot of a fleet (:class:`FleetMember`)."""

    @property
    def time(self) -> float: ...  # sim time (s)

    def teleport(self, pose: Pose2D) -> bool: ...

    def drop_lidar(self, duration_s: float) -> None: ...

    def drop_obstacle(self, obstacle: DroppedObstacle) -> bool: ...


class FleetMember:
    """Robot ``name`` of ``fleet`` as a WorldTarget: its teleports and the obstacles dropped through it go
    through the Fleet (which checks them against every robot); its lidar dropout is its own."""

    def __init__(self, fleet: Fleet, name: str) -> None:
        self.fleet, self.name = fleet, name

    @property
    def time(self) -> float:
        return self.fleet.time

    def teleport(self, pose: Pose2D) -> bool:
        return self.fleet.teleport(self.name, pose)

    def drop_lidar(self, duration_s: float) -> None:
        self.fleet.robot(self.name).drop_lidar(duration_s)

    def drop_obstacle(self, obstacle: DroppedObstacle) -> bool:
        return self.fleet.drop_obstacle(obstacle)


class WorldInputs:
    """Subscribes ``node`` to ``topics`` (each under ``prefix``, "" or ``robot1/``) and applies what
    arrives to ``sim``."""

    def __init__(self, node: Node, sim: WorldTarget, qos: QoSProfile, prefix: str = "",
                 topics: Sequence[str] = ALL_TOPICS) -> None:
        self.node, self.sim = node, sim
        self.label = f"{prefix.rstrip('/')}: " if prefix else ""   # in log lines, after "sim2d: "
        callbacks = {TELEPORT_TOPIC: (PoseStamped, self._on_teleport),
                     LIDAR_DROPOUT_TOPIC: (Float64, self._on_lidar_dropout),
                     SPAWN_OBSTACLE_TOPIC: (Marker, self._on_spawn_obstacle)}
        for topic in topics:
            msg_type, callback = callbacks[topic]
            node.create_subscription(msg_type, prefix + topic, callback, qos)  # type: ignore[arg-type]

    def _on_teleport(self, msg: PoseStamped) -> None:
        logger = self.node.get_logger()
        if msg.header.frame_id not in ("", messages.MAP_FRAME):
            logger.warning(f"sim2d: {self.label}teleport ignored: frame {msg.header.frame_id!r} is not 'map'")
            return
        pose = Pose2D(msg.pose.position.x, msg.pose.position.y, yaw_of(msg.pose.orientation))
        if not self.sim.teleport(pose):
            logger.warning(f"sim2d: {self.label}teleport to {pose} refused: footprint overlaps an obstacle")

    def _on_lidar_dropout(self, msg: Float64) -> None:
        logger = self.node.get_logger()
        if not math.isfinite(msg.data):
            logger.warning(f"sim2d: {self.label}lidar dropout of {msg.data} s refused: not a finite duration")
            return
        self.sim.drop_lidar(msg.data)
        state = f"for {msg.data:g} s of sim time" if msg.data > 0 else "ended"
        logger.info(f"sim2d: {self.label}lidar dropout {state} at sim time {self.sim.time:.3f} s "
                    "(every beam +inf)")

    def _on_spawn_obstacle(self, msg: Marker) -> None:
        logger = self.node.get_logger()
        try:
            obstacle = messages.obstacle_from_marker(msg)
        except ValueError as error:
            logger.warning(f"sim2d: spawn_obstacle ignored: {error}")
            return
        where = f"({obstacle.x:g}, {obstacle.y:g}) radius {obstacle.radius:g} m"
        if self.sim.drop_obstacle(obstacle):
            logger.info(f"sim2d: obstacle at {where} dropped at sim time {self.sim.time:.3f} s")
        else:
            logger.warning(f"sim2d: obstacle at {where} refused: it overlaps a robot")
