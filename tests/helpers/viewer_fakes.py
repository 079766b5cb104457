"""Fakes for the viewer tests: what map_server, AMCL, the costmaps, planner and controller, the waypoint
panel, a SMACC2 machine and bt_navigator publish.

Each fake owns publishers on a node the test created (so the test's context and executor own it)
and publishes exactly the messages and QoS the real producers use (nav2.md §2, smacc2.md §1).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from action_msgs.msg import GoalInfo, GoalStatus, GoalStatusArray
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point32, PolygonStamped, Pose, PoseStamped
from nav2_msgs.msg import BehaviorTreeLog, BehaviorTreeStatusChange, Particle, ParticleCloud
from nav_msgs.msg import OccupancyGrid, Path
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from smacc2_msgs.msg import (
    SmaccEvent,
    SmaccState,
    SmaccStateMachine,
    SmaccStatus,
    SmaccTransition,
    SmaccTransitionLogEntry,
)
from visualization_msgs.msg import Marker, MarkerArray

from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg
from ros_tools.tf.transform import Transform

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
KEEP_LAST_1 = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
#: AMCL's /particle_cloud: best effort, so a viewer subscribing reliable would never match it.
BEST_EFFORT = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT)
#: What an action server's ``_action/status`` topic offers (rclpy's qos_profile_action_status_default).
ACTION_STATUS = LATCHED

XyYaw = tuple[float, float, float]


def pose_msg(x: float, y: float, yaw: float) -> Pose:
    """A planar pose as a geometry_msgs/Pose."""
    pose = Pose()
    pose.position.x, pose.position.y = x, y
    pose.orientation.z, pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return pose


def particle_cloud(poses: Sequence[XyYaw], frame: str = "map") -> ParticleCloud:
    """AMCL's nav2_msgs/ParticleCloud with equal weights."""
    msg = ParticleCloud(particles=[Particle(pose=pose_msg(*p), weight=1.0 / len(poses)) for p in poses])
    msg.header.frame_id = frame
    return msg


def path(poses: Sequence[XyYaw], frame: str = "map") -> Path:
    """A nav_msgs/Path as the planner (/plan) or the controller (/local_plan, odom frame) publishes."""
    msg = Path()
    msg.header.frame_id = frame
    for p in poses:
        stamped = PoseStamped(pose=pose_msg(*p))
        stamped.header.frame_id = frame
        msg.poses.append(stamped)
    return msg


def footprint(points: Sequence[tuple[float, float]], frame: str = "odom") -> PolygonStamped:
    """The local costmap's published_footprint: the robot outline already placed in ``frame``."""
    msg = PolygonStamped()
    msg.header.frame_id = frame
    msg.polygon.points = [Point32(x=float(x), y=float(y)) for x, y in points]
    return msg


def waypoint_markers(poses: Sequence[XyYaw], frame: str = "map") -> MarkerArray:
    """What Nav2's RViz panel publishes on /waypoints: an arrow and a number label per waypoint."""
    markers = []
    for i, p in enumerate(poses):
        for kind in (Marker.ARROW, Marker.TEXT_VIEW_FACING):
            marker = Marker(id=2 * i + (kind == Marker.TEXT_VIEW_FACING), type=kind, action=Marker.ADD,
                            pose=pose_msg(*p), text=str(i + 1) if kind == Marker.TEXT_VIEW_FACING else "")
            marker.header.frame_id = frame
            markers.append(marker)
    return MarkerArray(markers=markers)


def goal_statuses(goals: Sequence[tuple[int, int]]) -> GoalStatusArray:
    """An action's status list from ``(GoalStatus code, acceptance stamp in s)`` per goal."""
    return GoalStatusArray(status_list=[
        GoalStatus(status=code, goal_info=GoalInfo(stamp=Time(sec=sec))) for code, sec in goals])


def occupancy_grid(cells: np.ndarray, resolution: float, origin: tuple[float, float],
                   frame: str = "map") -> OccupancyGrid:
    """An OccupancyGrid from an int8 array whose row 0 is the bottom row (the message's layout)."""
    msg = OccupancyGrid()
    msg.header.frame_id = frame
    msg.info.resolution = resolution
    msg.info.height, msg.info.width = cells.shape
    msg.info.origin.position.x, msg.info.origin.position.y = origin
    msg.info.origin.orientation.w = 1.0
    msg.data = cells.astype(np.int8).ravel().tolist()
    return msg


def map_from_file(yaml_path: str) -> OccupancyGrid:
    """A map_server map as map_server would publish it."""
    from nav_stack.core.map_io import load_map

    loaded = load_map(yaml_path)
    return occupancy_grid(loaded.data, loaded.spec.resolution, (loaded.spec.origin_x, loaded.spec.origin_y))


def marker_costmap(size: float, resolution: float, mark: tuple[float, float],
                   frame: str = "map") -> OccupancyGrid:
    """A free square costmap centred on the origin with one lethal 5x5-cell block at ``mark`` (m).

    The block sits off every symmetry axis, so a viewer that flips or mirrors grids draws it elsewhere.
    """
    n = round(size / resolution)
    cells = np.zeros((n, n), dtype=np.int8)
    col, row = round((mark[0] + size / 2) / resolution), round((mark[1] + size / 2) / resolution)
    cells[row - 2:row + 3, col - 2:col + 3] = 100
    return occupancy_grid(cells, resolution, (-size / 2, -size / 2), frame)


def publish_static(node: Node,
                   transforms: Sequence[tuple[str, str, Transform]]) -> StaticTransformBroadcaster:
    """Latch ``(parent, child, transform)`` triples on /tf_static (e.g. AMCL's map → odom stand-in)."""
    broadcaster = StaticTransformBroadcaster(node)
    broadcaster.send(transform_to_msg(t, parent, child, Time()) for parent, child, t in transforms)
    return broadcaster


# ---------------------------------------------------------------- SMACC2 introspection
FAKE_SM = "sm_fake"
#: (state, [(event, target, tag)]) of a small machine with a retry loop, in SMACC2's full-name style.
FAKE_STATES = [
    ("StAcquireSensors", [("EvCbSuccess", "StNavigate", "SUCCESS")]),
    ("StNavigate", [("EvCbSuccess", "StDock", "SUCCESS"), ("EvCbFailure", "StRecover", "ABORT")]),
    ("StRecover", [("EvCbSuccess", "StNavigate", "SUCCESS")]),
    ("StDock", []),
]


def _transition(source: str, target: str, tag: str, event: str, index: int = 0) -> SmaccTransition:
    return SmaccTransition(index=index, transition_name=f"{source}->{target}", transition_type=tag,
                           source_state_name=f"{FAKE_SM}::{source}",
                           destiny_state_name=f"{FAKE_SM}::{target}",
                           event=SmaccEvent(event_type=event, event_object_tag="OrNavigation",
                                            event_source="ClNav2Z", label=event))


class FakeSmacc:
    """Publishes a machine's description, status and transition log like SMACC2 does."""

    def __init__(self, node: Node, name: str = FAKE_SM) -> None:
        prefix = f"/{name}/smacc"
        self.node = node
        self.pub_description = node.create_publisher(SmaccStateMachine, f"{prefix}/state_machine_description",
                                                     KEEP_LAST_1)
        self.pub_status = node.create_publisher(SmaccStatus, f"{prefix}/status", KEEP_LAST_1)
        self.pub_log = node.create_publisher(SmaccTransitionLogEntry, f"{prefix}/transition_log", KEEP_LAST_1)
        self.current = FAKE_STATES[0][0]

    def description(self) -> SmaccStateMachine:
        states = []
        for i, (name, transitions) in enumerate(FAKE_STATES):
            edges = [_transition(name, target, tag, event, j)
                     for j, (event, target, tag) in enumerate(transitions)]
            states.append(SmaccState(index=i, name=f"{FAKE_SM}::{name}", level=0, transitions=edges))
        return SmaccStateMachine(states=states)

    def publish(self) -> None:
        """Description and status (SMACC2 republishes both every 0.5 s)."""
        self.pub_description.publish(self.description())
        self.pub_status.publish(SmaccStatus(current_states=[self.current], global_variable_names=["retries"],
                                            global_variable_values=["0"]))

    def transition(self, target: str, tag: str, event: str) -> None:
        entry = SmaccTransitionLogEntry(transition=_transition(self.current, target, tag, event))
        entry.timestamp = self.node.get_clock().now().to_msg()
        self.current = target
        self.pub_log.publish(entry)
        self.publish()


def bt_log(changes: Sequence[tuple[str, int, str, str]]) -> BehaviorTreeLog:
    """A nav2_msgs/BehaviorTreeLog from ``(node_name, uid, previous, current)`` changes."""
    return BehaviorTreeLog(event_log=[
        BehaviorTreeStatusChange(node_name=name, uid=uid, previous_status=prev, current_status=cur)
        for name, uid, prev, cur in changes])


def map_to_odom(x: float, y: float, yaw: float) -> tuple[str, str, Transform]:
    """The map → odom transform AMCL would publish when odom started at (x, y, yaw) in the map."""
    return ("map", "odom", Transform.from_xy_yaw(x, y, yaw))

