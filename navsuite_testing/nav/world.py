"""The world around the nav servers in integration tests: sim2d, /map, map→odom, and a spun executor.

* :func:`start_sim` runs ``python -m sim2d.ros.cli`` (ideal odometry, spawn (-2.0, -0.5, 0)).
* :class:`WorldNode` publishes /map from maps/turtlebot3_world.yaml (optionally with pillars cut out,
  to test scan marking) and the static map→odom transform that AMCL would publish. sim2d's odom
  frame starts at the spawn pose, so with ideal odometry map→odom is exactly the spawn pose.
* :class:`Harness` spins server nodes and test probes on one MultiThreadedExecutor in a background
  thread, so tests wait on futures and messages with ``wait_until`` (deadline-polled, no sleeps).
"""

from __future__ import annotations

import os
import subprocess
import tempfile
import threading
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from nav_msgs.msg import OccupancyGrid, Odometry
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import UInt32
from std_srvs.srv import Empty

from nav_stack.core.map_io import load_map
from nav_stack.ros.common.conversions import occupancy_msg
from navsuite_testing.ros import REPO, start_python, stop_process, wait_until
from ros_tools.geometry import yaw_of
from ros_tools.runtime.actions import send_until_acknowledged
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.requests import call_until_answered
from ros_tools.runtime.runner import spin_until_shutdown
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg

SPAWN = (-2.0, -0.5, 0.0)
CLOCK_RATE = 50.0  # /clock messages per sim second
MAP_YAML = REPO / "maps" / "turtlebot3_world.yaml"
PARAMS_FILE = REPO / "config" / "nav2_params.yaml"
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


def ideal_odometry_params() -> Path:
    """config/sim2d.yaml with ``odometry.ideal: true`` and a 50 Hz /clock, written to a temporary file.

    sim2d's parameter file values override ``-p`` arguments, so the switches go into a file. Every
    use_sim_time node handles each /clock message in Python; 50 Hz halves that load on a 2-core
    machine and still ticks a 20 Hz controller within 20 ms.
    """
    doc = yaml.safe_load((REPO / "config" / "sim2d.yaml").read_text())
    params = doc["sim2d"]["ros__parameters"]
    params.setdefault("odometry", {})["ideal"] = True
    params["clock_rate"] = CLOCK_RATE
    handle, name = tempfile.mkstemp(prefix="sim2d_ideal_", suffix=".yaml")
    with os.fdopen(handle, "w") as out:
        yaml.safe_dump(doc, out)
    return Path(name)


def start_sim(rtf: float | str = 3.0, stamped: bool = False, lockstep: bool = False) -> subprocess.Popen[str]:
    """sim2d with ideal odometry at the TB3 spawn pose; stop it with ``stop_process``.

    ``lockstep``: the simulator waits for whichever lockstep participants report (none are expected,
    so it runs freely until a test's participant joins; see tests/integration/nav_stack/
    test_controller_server.py).
    """
    args = ["--world", "turtlebot3_world", "--robot", "waffle", "--rtf", str(rtf),
            "--x", str(SPAWN[0]), "--y", str(SPAWN[1]), "--yaw", str(SPAWN[2]),
            "--params-file", str(ideal_odometry_params())]
    if stamped:
        args.append("--stamped")
    if lockstep:
        args.append("--lockstep")
    return start_python("sim2d.ros.cli", args)


def server_args() -> list[str]:
    """cli_args giving a node the project's nav2_params.yaml."""
    return ["--ros-args", "--params-file", str(PARAMS_FILE)]


def sim_time_override() -> list[Any]:
    """``parameter_overrides`` that put a node on sim2d's /clock."""
    from rclpy.parameter import Parameter

    return [Parameter("use_sim_time", value=True)]


def map_without(centres: Iterable[tuple[float, float]], radius: float = 0.25) -> OccupancyGrid:
    """The TB3 map with every occupied cell within ``radius`` of the given points made free."""
    loaded = load_map(MAP_YAML)
    data, spec = loaded.data.copy(), loaded.spec
    my, mx = np.mgrid[0 : spec.height, 0 : spec.width]
    wx, wy = spec.cell_to_world(mx, my)
    for cx, cy in centres:
        data[np.hypot(wx - cx, wy - cy) <= radius] = 0
    return occupancy_msg(data, spec, "map", _zero_stamp())


def _zero_stamp() -> Any:
    from builtin_interfaces.msg import Time

    return Time()


class WorldNode(Node):
    """Publishes /map (latched) and map→odom (static), watches sim2d's ground truth and collisions."""

    def __init__(self, removed_pillars: Sequence[tuple[float, float]] = (), **kwargs: Any) -> None:
        super().__init__("test_world", **kwargs)
        self.map_pub = self.create_publisher(OccupancyGrid, "/map", LATCHED)
        self.map_pub.publish(map_without(removed_pillars))
        self.tf_static = StaticTransformBroadcaster(self)
        spawn = Transform.from_xy_yaw(*SPAWN)
        self.tf_static.send([transform_to_msg(spawn, "map", "odom", _zero_stamp())])
        self.truth: Odometry | None = None
        self.collisions: int | None = None
        self.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        self.create_subscription(UInt32, "/sim2d/collision_count", self._on_collisions, LATCHED)
        self.reset_client = self.create_client(Empty, "/sim2d/reset")

    def _on_truth(self, msg: Odometry) -> None:
        self.truth = msg

    def _on_collisions(self, msg: UInt32) -> None:
        self.collisions = msg.data

    def pose(self) -> tuple[float, float, float]:
        """Ground-truth (x, y, yaw) in the map frame."""
        assert self.truth is not None, "no ground truth received yet"
        p = self.truth.pose.pose.position
        return p.x, p.y, yaw_of(self.truth.pose.pose.orientation)

    def call(self, client: Any, request: Any, timeout: float = 10.0) -> Any:
        wait_until(client.service_is_ready, timeout, f"service {client.srv_name}")
        return call_until_answered(client, request, timeout)

    def reset_sim(self) -> None:
        """Robot back to the spawn pose (odometry and collision count restart)."""
        self.call(self.reset_client, Empty.Request())


class Harness:
    """Nodes spun in a background thread by the executor production uses (one thread, the
    EventsExecutor unless NAVSUITE_EXECUTOR says otherwise); ``close()`` in ``finally``."""

    def __init__(self, context: Any) -> None:
        self.context = context
        self.executor = make_executor(context=context)
        self._stopping = False
        self.nodes: list[Node] = []
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        spin_until_shutdown(self.executor, "test harness", lambda: self._stopping)

    def add(self, *nodes: Node) -> None:
        for node in nodes:
            self.nodes.append(node)
            self.executor.add_node(node)

    def bring_up(self, server: Any) -> None:
        """Configure and activate a lifecycle server (as the lifecycle manager would)."""
        from rclpy.lifecycle import TransitionCallbackReturn

        assert server.trigger_configure() == TransitionCallbackReturn.SUCCESS, "configure failed"
        assert server.trigger_activate() == TransitionCallbackReturn.SUCCESS, "activate failed"

    def stop(self) -> None:
        """Stop spinning: after this, entities can be destroyed without racing the spinning thread."""
        self._stopping = True  # see ros_tools.runtime.runner.spin_until_shutdown
        self._thread.join(timeout=5.0)
        self.executor.shutdown(timeout_sec=5.0)

    def close(self) -> None:
        """Stop spinning (if :meth:`stop` has not), then destroy the nodes."""
        if not self._stopping:
            self.stop()
        for node in self.nodes:
            node.destroy_node()


DISCOVERY_WAIT = 60.0  # s (wall) a new client may take to discover its server (see send_goal)


def send_goal(client: Any, goal: Any, timeout: float = 15.0, feedback: Callable[[Any], None] | None = None
              ) -> Any:
    """Send an action goal and return the accepted goal handle.

    ``timeout`` bounds the acknowledgement; discovering the server gets DISCOVERY_WAIT s (wall) of
    its own, a safety net: a client created mid-test can take over 15 s to discover a server late
    in a loaded full-suite run (CI run U), and nothing is measured by that wait."""
    wait_until(lambda: client.server_is_ready(), max(timeout, DISCOVERY_WAIT),
               f"action server {client._action_name}")
    handle = send_until_acknowledged(client, goal, timeout, feedback_callback=feedback).result()
    assert handle.accepted, f"{type(goal).__name__} rejected"
    return handle


def get_result(handle: Any, timeout: float) -> Any:
    """Wait for an accepted goal's result (status, result message)."""
    future = handle.get_result_async()
    wait_until(future.done, timeout, "the action result")
    response = future.result()
    return response.status, response.result


__all__ = ["Harness", "WorldNode", "get_result", "send_goal", "server_args", "start_sim", "stop_process"]
