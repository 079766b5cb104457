"""The events that are one request to sim2d: each kind's (ready, apply) pair for the injector.

Topics and services (sim2d.ros.world_inputs, sim2d.ros.fault_inputs, sim2d.ros.sim_node; root namespace):

* ``kidnap`` [x, y, yaw] -> PoseStamped on /sim2d/teleport;
* ``lidar_dropout`` s -> Float64 on /sim2d/lidar_dropout;
* ``obstacle`` [x, y, radius] and ``obstacle_on_path`` {ahead, radius} -> a CYLINDER Marker on
  /sim2d/spawn_obstacle; for ``obstacle_on_path`` the centre is ``ahead`` m along the planner's latest
  /plan from the point nearest the robot's true pose (/ground_truth), and never closer than
  GOAL_CLEARANCE + radius to the plan's end: an obstacle on the goal would only show that the goal
  cannot be reached;
* ``topic_loss`` {topic, duration} -> KeyValue on /sim2d/topic_loss;
* ``odom_slip`` {scale, duration} -> Float64MultiArray [scale, duration] on /sim2d/odometry_slip;
* ``clock_pause`` s (wall) -> SetBool(true) on /sim2d/pause, SetBool(false) that many wall s later.

``ready()`` is true once sim2d subscribes (or serves); ``apply(value, stamp)`` sends and returns what
the "applied" line says, or raises ValueError when the event cannot be placed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from ros_tools.geometry import set_yaw

TELEPORT_TOPIC = "/sim2d/teleport"
LIDAR_DROPOUT_TOPIC = "/sim2d/lidar_dropout"
SPAWN_OBSTACLE_TOPIC = "/sim2d/spawn_obstacle"
TOPIC_LOSS_TOPIC = "/sim2d/topic_loss"
ODOMETRY_SLIP_TOPIC = "/sim2d/odometry_slip"
PAUSE_SERVICE = "/sim2d/pause"
GOAL_CLEARANCE = 0.5  # m kept free between an obstacle_on_path's edge and the end of the path
SIM_EVENTS = ("kidnap", "lidar_dropout", "obstacle", "obstacle_on_path", "topic_loss", "odom_slip",
              "clock_pause")
Applier = tuple[Callable[[], bool], Callable[[Any, Any], str]]


def point_along(path: Sequence[tuple[float, float]], robot: tuple[float, float], ahead: float,
                end_clearance: float) -> tuple[float, float] | None:
    """The point ``ahead`` m along ``path`` (map frame, m) from its vertex nearest ``robot``, pulled back
    to stay ``end_clearance`` m (arc length) before the path's end; None when the rest of the path is
    too short for that."""
    if len(path) < 2:
        return None
    start = min(range(len(path)), key=lambda i: math.dist(path[i], robot))
    remaining = sum(math.dist(a, b) for a, b in zip(path[start:], path[start + 1:], strict=False))
    distance = min(ahead, remaining - end_clearance)
    if distance <= 0.0:
        return None
    for a, b in zip(path[start:], path[start + 1:], strict=False):
        length = math.dist(a, b)
        if distance <= length and length > 0.0:
            t = distance / length
            return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
        distance -= length
    return path[-1]


def sim_applier(node: Any, kind: str, qos: Any, steady: Any) -> Applier:
    """(ready, apply) of a SIM_EVENTS ``kind`` on ``node``; ``steady``: the clock of clock_pause's resume."""
    if kind == "clock_pause":
        return _clock_pause(node, steady)
    if kind == "obstacle_on_path":
        return _obstacle_on_path(node, qos)
    from diagnostic_msgs.msg import KeyValue
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import Float64, Float64MultiArray
    from visualization_msgs.msg import Marker

    msg_type, topic = {"kidnap": (PoseStamped, TELEPORT_TOPIC), "obstacle": (Marker, SPAWN_OBSTACLE_TOPIC),
                       "lidar_dropout": (Float64, LIDAR_DROPOUT_TOPIC),
                       "topic_loss": (KeyValue, TOPIC_LOSS_TOPIC),
                       "odom_slip": (Float64MultiArray, ODOMETRY_SLIP_TOPIC)}[kind]
    publisher = node.create_publisher(msg_type, topic, qos)

    def apply(value: Any, stamp: Any) -> str:
        if kind == "lidar_dropout":
            publisher.publish(Float64(data=float(value)))
            return f"{float(value):g} s"
        if kind == "topic_loss":
            publisher.publish(KeyValue(key=value["topic"], value=f"{float(value['duration']):g}"))
            return f"{value['topic']} for {float(value['duration']):g} s"
        if kind == "odom_slip":
            publisher.publish(Float64MultiArray(data=[float(value["scale"]), float(value["duration"])]))
            return f"x{float(value['scale']):g} for {float(value['duration']):g} s"
        numbers = [float(v) for v in value]
        if kind == "kidnap":
            x, y, yaw = numbers
            msg = PoseStamped()
            msg.pose.position.x, msg.pose.position.y = x, y
            set_yaw(msg.pose.orientation, yaw)
            msg.header.frame_id, msg.header.stamp = "map", stamp
            publisher.publish(msg)
        else:
            publisher.publish(cylinder(numbers[0], numbers[1], numbers[2], stamp))
        return "[" + ", ".join(f"{v:g}" for v in numbers) + "]"

    return (lambda: publisher.get_subscription_count() > 0), apply


def cylinder(x: float, y: float, radius: float, stamp: Any) -> Any:
    """sim2d's spawn_obstacle request: a CYLINDER Marker of ``radius`` m at (x, y) in the map frame."""
    from visualization_msgs.msg import Marker

    msg = Marker(type=Marker.CYLINDER, action=Marker.ADD)
    msg.pose.position.x, msg.pose.position.y, msg.pose.orientation.w = x, y, 1.0
    msg.scale.x = msg.scale.y = 2.0 * radius
    msg.scale.z = 0.5  # a height for RViz only; sim2d is planar
    msg.header.frame_id, msg.header.stamp = "map", stamp
    return msg


def _obstacle_on_path(node: Any, qos: Any) -> Applier:
    from nav_msgs.msg import Odometry, Path
    from visualization_msgs.msg import Marker

    publisher = node.create_publisher(Marker, SPAWN_OBSTACLE_TOPIC, qos)
    heard: dict[str, Any] = {}
    node.create_subscription(Path, "/plan", lambda msg: heard.__setitem__("plan", msg), qos)
    node.create_subscription(Odometry, "/ground_truth", lambda msg: heard.__setitem__("truth", msg), qos)

    def apply(value: Any, stamp: Any) -> str:
        path = [(p.pose.position.x, p.pose.position.y) for p in heard["plan"].poses]
        truth = heard["truth"].pose.pose.position
        radius = float(value["radius"])
        point = point_along(path, (truth.x, truth.y), float(value["ahead"]), GOAL_CLEARANCE + radius)
        if point is None:
            raise ValueError(f"the path left ({len(path)} poses) is too short for an obstacle "
                             f"{float(value['ahead']):g} m ahead")
        publisher.publish(cylinder(point[0], point[1], radius, stamp))
        return f"[{point[0]:.3g}, {point[1]:.3g}, {radius:g}]"

    def ready() -> bool:
        return publisher.get_subscription_count() > 0 and "plan" in heard and "truth" in heard

    return ready, apply


def _clock_pause(node: Any, steady: Any) -> Applier:
    from std_srvs.srv import SetBool

    client = node.create_client(SetBool, PAUSE_SERVICE)

    def apply(value: Any, _stamp: Any) -> str:
        seconds = float(value)
        client.call_async(SetBool.Request(data=True))

        def resume() -> None:
            node.destroy_timer(timer)
            client.call_async(SetBool.Request(data=False))
            print(f"injector: clock resumed after {seconds:g} s wall", flush=True)

        timer = node.create_timer(seconds, resume, clock=steady)
        return f"for {seconds:g} s wall"

    return client.service_is_ready, apply
