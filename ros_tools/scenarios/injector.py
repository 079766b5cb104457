"""Apply a scenario's events at their sim times: a small node that watches /clock and acts on the world.

Today: ``kidnap`` (a PoseStamped on sim2d's ``/sim2d/teleport``: the robot moves, odometry and AMCL
do not know). It is a lockstep participant (role ``scenario_events``), and it reports only once its
teleport publisher has matched the simulator's subscription; the farm also names the role in
nav-bringup's ``--participant`` list, so the simulator does not step before the injector is there and
never runs more than one lockstep lead (0.05 s) past an event's time. It stays up after its last event
until the worker stops it: a process that exits right after publishing may take the message (and its
lockstep leave) down with it, and the simulator would then wait 5 s wall for the silent participant.

Each applied event is printed as ``applied <kind> <value> at t=<sim s>`` (the worker keeps these lines).

Usage: ``python -m ros_tools.scenarios.injector '<json list of {"at": s, "kidnap": [x, y, yaw]}>'``.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Sequence
from typing import Any

TELEPORT_TOPIC = "/sim2d/teleport"  # sim2d's (sim2d.ros.sim_node.TELEPORT_TOPIC, resolved)
ROLE = "scenario_events"


def build_node(events: list[dict[str, Any]]) -> Any:
    """The injector node; ``events`` sorted by ``at`` (s)."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rosgraph_msgs.msg import Clock

    node = Node("scenario_events")
    publisher = node.create_publisher(PoseStamped, TELEPORT_TOPIC,
                                      QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
    pending = sorted(events, key=lambda event: float(event["at"]))

    def on_clock(msg: Clock) -> None:
        now = msg.clock.sec + msg.clock.nanosec * 1e-9
        while pending and now >= float(pending[0]["at"]) and publisher.get_subscription_count() > 0:
            event = pending.pop(0)
            x, y, yaw = (float(v) for v in event["kidnap"])
            pose = PoseStamped()
            pose.header.frame_id = "map"
            pose.header.stamp = msg.clock
            pose.pose.position.x, pose.pose.position.y = x, y
            pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
            publisher.publish(pose)
            print(f"applied kidnap [{x:g}, {y:g}, {yaw:g}] at t={now:.2f} s", flush=True)

    node.create_subscription(Clock, "/clock", on_clock,
                             QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
    node.scenario_ready = lambda: publisher.get_subscription_count() > 0  # type: ignore[attr-defined]
    return node


def main(argv: Sequence[str] | None = None) -> int:
    from ros_tools.runtime.runner import run_nodes

    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    events = json.loads(args[0])
    unsupported = [event for event in events if set(event) != {"at", "kidnap"}]
    if unsupported:
        print(f"injector: unsupported events {unsupported}", file=sys.stderr)
        return 2
    nodes: list[Any] = []

    def build() -> list[Any]:
        nodes.append(build_node(events))
        return nodes

    return run_nodes(build, role=ROLE, rclpy_args=["--ros-args", "-p", "use_sim_time:=true"],
                     ready=lambda: bool(nodes) and nodes[0].scenario_ready())


if __name__ == "__main__":
    sys.exit(main())
