"""Apply a scenario's events at their sim times: a small node that watches /clock and acts on the world.

Events (values as in the scenario file; each becomes one message to sim2d, or one signal):

* ``kidnap`` [x, y, yaw]: a PoseStamped on ``/sim2d/teleport`` (the robot moves; odometry and AMCL
  do not know);
* ``lidar_dropout`` s: a Float64 on ``/sim2d/lidar_dropout`` (every beam reads +inf for that much
  sim time: sim2d.core.disturbances says why that is the failure modelled);
* ``obstacle`` [x, y, radius]: a CYLINDER Marker on ``/sim2d/spawn_obstacle`` (map frame, m);
* ``kill_navigation``: SIGKILL of the process running bt_navigator and the controller, the lockstep
  participant ``nav2`` (or ``navigation``) whose pid it read on /lockstep/progress
  (ros_tools.scenarios.navigation_kill: why there, and the guard). The injector does it, not the
  worker, because only the injector follows sim time. nav-bringup then respawns the process (its
  ``use_respawn``; with ``--no-respawn`` the launch ends and the mission with STACK).

It is a lockstep participant (role ``scenario_events``) that reports only once every publisher it needs
has matched the simulator's subscription and, for ``kill_navigation``, once it has heard the
navigation process's pid; the farm also names the role in nav-bringup's
``--participant`` list, so the simulator does not step before the injector is there and never runs
more than one lockstep lead (0.05 s) past an event's time. An event waits while its channel is not
ready (no subscriber yet, no navigation pid heard yet), so none is lost. It stays up after its last
event until the worker stops it: a process that exits right after publishing may take the message
(and its lockstep leave) down with it, and the simulator would then wait 5 s wall for the silent
participant.

Each applied event is printed as ``applied <kind> <value> at t=<sim s>`` (the worker keeps these lines).

Usage: ``python -m ros_tools.scenarios.injector '<json list of {"at": s, "<kind>": value}>'``.
"""

from __future__ import annotations

import json
import math
import os
import sys
from collections.abc import Callable, Sequence
from typing import Any

from ros_tools.scenarios.navigation_kill import kill_navigation, navigation_pid

#: sim2d's topics (sim2d.ros.world_inputs, resolved in the root namespace)
TELEPORT_TOPIC = "/sim2d/teleport"
LIDAR_DROPOUT_TOPIC = "/sim2d/lidar_dropout"
SPAWN_OBSTACLE_TOPIC = "/sim2d/spawn_obstacle"
ROLE = "scenario_events"
KINDS = ("kidnap", "lidar_dropout", "obstacle", "kill_navigation")


def build_node(events: list[dict[str, Any]]) -> Any:
    """The injector node; ``events`` are applied in order of ``at`` (s of sim time)."""
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import Header

    from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC

    node = Node("scenario_events")
    reliable = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
    pending = sorted(events, key=lambda event: float(event["at"]))
    kinds = {_kind(event) for event in pending}
    navigation: list[int] = []  # the pid of the navigation process, once a report named it
    appliers: dict[str, tuple[Callable[[], bool], Callable[[Any, Any], str]]] = {}
    for kind in kinds - {"kill_navigation"}:
        appliers[kind] = _publishing(node, kind, reliable)
    if "kill_navigation" in kinds:
        def heard(msg: Header) -> None:
            pid = navigation_pid(msg.frame_id)
            if pid is not None and not navigation:
                navigation.append(pid)

        node.create_subscription(Header, PROGRESS_TOPIC, heard, PROGRESS_QOS)
        appliers["kill_navigation"] = (lambda: bool(navigation),
                                       lambda _value, _stamp: kill_navigation(navigation[0], os.getppid()))

    def on_clock(msg: Clock) -> None:
        now = msg.clock.sec + msg.clock.nanosec * 1e-9
        while pending and now >= float(pending[0]["at"]):
            kind = _kind(pending[0])
            ready, apply = appliers[kind]
            if not ready():
                return
            event = pending.pop(0)
            try:
                what = apply(event[kind], msg.clock)
            except OSError as error:  # the process is gone already, or not ours: say so, apply nothing
                print(f"injector: {kind} at t={now:.2f} s not applied: {error}", flush=True)
                continue
            print(f"applied {kind} {what} at t={now:.2f} s", flush=True)

    node.create_subscription(Clock, "/clock", on_clock, reliable)
    # Every channel, the navigation pid included: an injector that joined before it had heard the
    # pid let the simulator run past a kill's time (CI run CN: "at t=5.0" applied at 6.80 s).
    channels_ready = [ready for ready, _ in appliers.values()]
    node.scenario_ready = lambda: all(ready() for ready in channels_ready)  # type: ignore[attr-defined]
    return node


def _kind(event: dict[str, Any]) -> str:
    return next(key for key in event if key != "at")


def _publishing(node: Any, kind: str, qos: Any) -> tuple[Callable[[], bool], Callable[[Any, Any], str]]:
    """(ready, apply) of an event that is one message to sim2d: ready once sim2d subscribes."""
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import Float64
    from visualization_msgs.msg import Marker

    msg_type, topic = {"kidnap": (PoseStamped, TELEPORT_TOPIC), "obstacle": (Marker, SPAWN_OBSTACLE_TOPIC),
                       "lidar_dropout": (Float64, LIDAR_DROPOUT_TOPIC)}[kind]
    publisher = node.create_publisher(msg_type, topic, qos)

    def apply(value: Any, stamp: Any) -> str:
        if kind == "lidar_dropout":
            publisher.publish(Float64(data=float(value)))
            return f"{float(value):g} s"
        numbers = [float(v) for v in value]
        if kind == "kidnap":
            x, y, yaw = numbers
            msg = PoseStamped()
            msg.pose.position.x, msg.pose.position.y = x, y
            msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
        else:
            x, y, radius = numbers
            msg = Marker(type=Marker.CYLINDER, action=Marker.ADD)
            msg.pose.position.x, msg.pose.position.y, msg.pose.orientation.w = x, y, 1.0
            msg.scale.x = msg.scale.y = 2.0 * radius
            msg.scale.z = 0.5  # a height for RViz only; sim2d is planar
        msg.header.frame_id, msg.header.stamp = "map", stamp
        publisher.publish(msg)
        return "[" + ", ".join(f"{v:g}" for v in numbers) + "]"

    return (lambda: publisher.get_subscription_count() > 0), apply


def main(argv: Sequence[str] | None = None) -> int:
    from ros_tools.runtime.runner import run_nodes

    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    events = json.loads(args[0])
    unsupported = [event for event in events if not isinstance(event, dict) or len(event) != 2
                   or "at" not in event or _kind(event) not in KINDS]
    if unsupported:
        print(f"injector: unsupported events {unsupported} (kinds: {', '.join(KINDS)})", file=sys.stderr)
        return 2
    nodes: list[Any] = []

    def build() -> list[Any]:
        nodes.append(build_node(events))
        return nodes

    return run_nodes(build, role=ROLE, rclpy_args=["--ros-args", "-p", "use_sim_time:=true"],
                     ready=lambda: bool(nodes) and nodes[0].scenario_ready())


if __name__ == "__main__":
    sys.exit(main())
