"""``autonomy_node`` (console ``nav-autonomy``): the seed project's battery-aware patrol tree on ROS.

Loads a BehaviorTree.CPP v3/v4 tree (default: the seed's tree.xml unchanged) and a locations file,
registers the six seed node types (seed_nodes.py) and Nav2's ROS leaves (nav_stack.ros.bt_nodes: the
docking variant config/trees/seed_battery_patrol_docking.xml uses DockRobot and UndockRobot, run by
config/autonomy_docking.yaml) and ticks the tree every ``tick_period`` s of the node clock (sim time
under ``use_sim_time``). A cycle is one root SUCCESS or FAILURE; after
``max_cycles`` cycles (0 = never) the node halts the tree and exits 0.

Shown while it runs: every status change goes out as nav2_msgs/BehaviorTreeLog on
/behavior_tree_log (the live viewer and Nav2 tools read it), the structure as JSON on
/behavior_tree_structure (latched), the ascii tree with statuses in the log (at most every
``status_log_period`` wall s), and each root result as one log line; a root FAILURE (the seed's
normal outcome when the battery is empty) is a warning naming the leaf that failed.

Configuration errors (unknown node in the tree, missing or malformed location, bad parameter)
print one line naming the file and item and exit with code 2.

Nothing waits in a callback: the tick timer polls each running leaf (GoToPose's goal is a future with
done-callbacks, WaitSeconds compares tree times), so one executor thread (the EventsExecutor by
default, ``--executor single`` for rclpy's SingleThreadedExecutor) serves the whole node. Under
``use_sim_time`` the process takes part in lockstep as ``autonomy``.

    nav-autonomy --ros-args --params-file config/autonomy.yaml -p battery_source:=counter
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nav2_msgs.msg import BehaviorTreeLog, BehaviorTreeStatusChange
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import BatteryState
from std_msgs.msg import String

from nav_stack.core.bt import BehaviorTreeFactory, NodeStatus, Tree, TreeNode, ascii_tree
from nav_stack.ros.autonomy.battery import BatterySource, CounterBattery, TopicBattery, TopicBatteryParams
from nav_stack.ros.autonomy.locations import check_tree_locations, load_locations
from nav_stack.ros.autonomy.navigator import RosNavigator
from nav_stack.ros.autonomy.seed_nodes import SeedContext, register_seed_nodes
from nav_stack.ros.bt_nodes import BtRosContext, register_ros_nodes
from nav_stack.ros.common.params import declare_dataclass
from navsuite_data import resolve, searched
from ros_tools.runtime.executor import add_executor_argument
from ros_tools.runtime.timers import create_periodic_timer

BATTERY_SOURCES = ("topic", "counter")
EXIT_CONFIG = 2
CANCEL_ANSWER_WAIT = 2.0  # wall s the teardown waits for the server to answer the running goal's cancel
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


@dataclass(frozen=True)
class AutonomyParams:
    """Parameters of ``autonomy_node`` (s, fractions of a full charge).

    Attributes:
        tree_file: BT XML (v3 or v4); relative paths resolve against the working directory, then the
            shipped data (``config/...``: navsuite_data).
        location_file: ``name: [x, y, theta]`` in ``global_frame``.
        tick_period: s of node clock between ticks (the seed's 500 ms timer).
        max_cycles: stop after this many root SUCCESS/FAILURE results; 0 runs forever.
        battery_source: ``topic`` (/battery_state from the simulator) or ``counter`` (the seed's).
        battery_topic: sensor_msgs/BatteryState topic for ``topic``.
        low_threshold, charged_threshold, recharge_timeout: see battery.TopicBattery.
        server_timeout: wall s GoToPose waits for the NavigateToPose server.
        action_name: the NavigateToPose server.
        global_frame: frame of the locations and goals.
        status_log_period: minimum wall s between two ascii-tree log entries.
    """

    tree_file: str = "config/trees/seed_battery_patrol_v3.xml"
    location_file: str = "config/locations.yaml"
    tick_period: float = 0.5
    max_cycles: int = 0
    battery_source: str = "topic"
    battery_topic: str = "/battery_state"
    low_threshold: float = 0.2
    charged_threshold: float = 0.95
    recharge_timeout: float = 120.0
    server_timeout: float = 10.0
    action_name: str = "navigate_to_pose"
    global_frame: str = "map"
    status_log_period: float = 2.0

    def __post_init__(self) -> None:
        if self.battery_source not in BATTERY_SOURCES:
            raise ValueError(f"battery_source must be one of {', '.join(BATTERY_SOURCES)}, "
                             f"got {self.battery_source!r}")
        if not self.tick_period > 0.0:
            raise ValueError(f"tick_period must be > 0 s, got {self.tick_period}")
        if self.max_cycles < 0:
            raise ValueError(f"max_cycles must be >= 0, got {self.max_cycles}")


def existing_file(parameter: str, text: str) -> Path:
    """A file parameter's path: as given if it exists, else the shipped file of that name
    (navsuite_data.resolve); a ValueError names the parameter, the file and where it was looked for."""
    path = resolve(text)
    if not path.is_file():
        raise ValueError(f"{parameter}: no such file: {text} ({searched(text)})")
    return path


def tree_structure(tree: Tree) -> dict[str, Any]:
    """The tree as nested dicts ``{name, uid, type, children}`` (/behavior_tree_structure)."""

    def walk(node: TreeNode) -> dict[str, Any]:
        return {"name": node.name, "uid": node.uid, "type": node.registration_id,
                "children": [walk(child) for child in node.children_nodes()]}

    return walk(tree.root)


class AutonomyNode(Node):
    """Loads and ticks the tree; raises ValueError (one line: file and item) on bad configuration."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("autonomy_node", **kwargs)
        self.params = declare_dataclass(self, AutonomyParams)
        p = self.params
        self.battery: BatterySource
        if p.battery_source == "counter":
            self.battery = CounterBattery()
        else:
            self.battery = TopicBattery(TopicBatteryParams(p.low_threshold, p.charged_threshold,
                                                           p.recharge_timeout))
        self.location_file = existing_file("location_file", p.location_file)
        self.tree_file = existing_file("tree_file", p.tree_file)
        locations = load_locations(self.location_file)
        self.navigator = RosNavigator(self, p.action_name, p.global_frame)
        self.seed = SeedContext(self.navigator, self.battery, locations, p.server_timeout,
                                   log=self.get_logger())
        factory = BehaviorTreeFactory()
        register_seed_nodes(factory, self.seed)
        self.ros_leaves = BtRosContext(self)  # Nav2's leaves (DockRobot, UndockRobot, ...) on this node
        register_ros_nodes(factory, self.ros_leaves)
        self.tree = factory.create_tree_from_file(self.tree_file)
        check_tree_locations(self.tree, locations, str(self.location_file))
        self.cycle_results: list[NodeStatus] = []
        self.cycle_durations: list[float] = []  # s of node clock per cycle
        self._cycle_start: float | None = None
        self.finished = False
        self._events: list[BehaviorTreeStatusChange] = []
        self._failed_leaf = ""
        self._last_ascii = -float("inf")
        self._last_wait_log = -float("inf")
        self.tree.add_status_listener(self._on_status)
        self._log_pub = self.create_publisher(BehaviorTreeLog, "/behavior_tree_log", 10)
        self._structure_pub = self.create_publisher(String, "/behavior_tree_structure", LATCHED)
        self._structure_pub.publish(String(data=json.dumps(tree_structure(self.tree))))
        if isinstance(self.battery, TopicBattery):
            self.create_subscription(BatteryState, p.battery_topic, self._on_battery, 10)
        self._timer = create_periodic_timer(self, p.tick_period, self._tick)
        self.get_logger().info(f"tree {self.tree_file} ({len(self.tree.nodes)} nodes), "
                               f"{len(locations)} locations from {self.location_file}, "
                               f"battery {p.battery_source}, "
                               f"tick {p.tick_period:g} s, max_cycles {p.max_cycles or 'unlimited'}")

    # ------------------------------------------------------------------ inputs
    def _on_battery(self, msg: BatteryState) -> None:
        assert isinstance(self.battery, TopicBattery)
        self.battery.update(float(msg.percentage))

    def _on_status(self, node: TreeNode, previous: NodeStatus, current: NodeStatus) -> None:
        event = BehaviorTreeStatusChange(node_name=node.name, uid=node.uid, previous_status=previous.value,
                                         current_status=current.value)
        event.timestamp = self.get_clock().now().to_msg()
        self._events.append(event)
        if current is NodeStatus.FAILURE and not node.children_nodes():
            self._failed_leaf = node.name

    # ------------------------------------------------------------------ ticking
    def _tick(self) -> None:
        if self.finished:
            return
        if not self.battery.ready():
            wall = time.monotonic()
            if wall - self._last_wait_log > 5.0:
                self._last_wait_log = wall
                self.get_logger().info(f"waiting for {self.params.battery_topic} before the first tick")
            return
        now = self.get_clock().now().nanoseconds * 1e-9
        if self._cycle_start is None:
            self._cycle_start = now
        status = self.tree.tick_once(now)
        self._publish_changes(force_ascii=status.is_completed)
        if status.is_completed:
            self.cycle_durations.append(now - self._cycle_start)
            self._cycle_start = None
            self._end_cycle(status)

    def _publish_changes(self, force_ascii: bool) -> None:
        if not self._events:
            return
        msg = BehaviorTreeLog(event_log=self._events)
        msg.timestamp = self.get_clock().now().to_msg()
        self._log_pub.publish(msg)
        self._events = []
        wall = time.monotonic()
        if force_ascii or wall - self._last_ascii >= self.params.status_log_period:
            self._last_ascii = wall
            self.get_logger().info("tree status:\n" + ascii_tree(self.tree).rstrip())

    def _end_cycle(self, status: NodeStatus) -> None:
        self.cycle_results.append(status)
        n = len(self.cycle_results)
        took = f"in {self.cycle_durations[-1]:.1f} s"
        if status is NodeStatus.SUCCESS:
            self.get_logger().info(f"cycle {n}: root SUCCESS {took} (battery {self.battery.describe()})")
        else:
            self.get_logger().warning(
                f"cycle {n}: root FAILURE at '{self._failed_leaf}' {took} "
                f"(battery {self.battery.describe()}); "
                "the tree starts over on the next tick (with an empty battery: recharge first)")
        self._failed_leaf = ""
        if self.params.max_cycles and n >= self.params.max_cycles:
            self.get_logger().info(f"finished {n} cycles; visited: {', '.join(self.seed.trace)}")
            self.stop()

    def stop(self) -> None:
        """Halt the tree (cancels a running NavigateToPose goal) and stop ticking."""
        if self.finished:
            return
        self.finished = True
        self._timer.cancel()
        self.tree.halt()
        self._publish_changes(force_ascii=False)

    def destroy_node(self) -> None:
        """Halt (cancelling a running goal while the action client still exists), then destroy."""
        self.stop()
        self.navigator.destroy()
        self.ros_leaves.destroy()
        super().destroy_node()


def _ros_args(argv: Sequence[str]) -> tuple[list[str], str | None]:
    """(rclpy arguments, ``--executor`` choice): the flags become ``-p`` parameters; everything after
    --ros-args passes through."""
    argv = list(argv)
    tail = argv[argv.index("--ros-args"):] if "--ros-args" in argv else []
    head = argv[: len(argv) - len(tail)]
    parser = argparse.ArgumentParser(
        prog="nav-autonomy",
        description="The seed's battery-aware behavior-tree autonomy: runs a BehaviorTree.CPP tree "
                    "(v3 or v4) over named locations with NavigateToPose. Flags set the node's "
                    "parameters; pass others after --ros-args (-p name:=value, --params-file FILE).",
    )
    parser.add_argument("--tree", dest="tree_file", help=f"BT XML (default {AutonomyParams.tree_file})")
    parser.add_argument("--locations", dest="location_file",
                        help=f"name: [x, y, theta] file (default {AutonomyParams.location_file})")
    parser.add_argument("--battery-source", choices=("topic", "counter"),
                        help="/battery_state from the simulator (default) or the seed's counter")
    parser.add_argument("--max-cycles", type=int, help="stop after N root results (default 0: forever)")
    add_executor_argument(parser)
    args = vars(parser.parse_args(head))
    executor = args.pop("executor")
    params = [f"{name}:={value}" for name, value in args.items() if value is not None]
    if not params:
        return ["nav-autonomy", *tail], executor
    if not tail:
        tail = ["--ros-args"]
    return ["nav-autonomy", *tail, *(arg for param in params for arg in ("-p", param))], executor


def main(argv: Sequence[str] | None = None) -> int:
    """Run the node until ``max_cycles`` or Ctrl-C; exit 2 with one line on a configuration error."""
    args, executor_kind = _ros_args(sys.argv[1:] if argv is None else argv)
    from ros_tools.runtime.runner import run_nodes

    def halt(executor: Any, nodes: Sequence[Any]) -> None:
        """Halt first: a running goal is cancelled while its client still exists (and, in lockstep,
        while the simulator still steps for the answer)."""
        node = nodes[0]
        node.stop()
        deadline = time.monotonic() + CANCEL_ANSWER_WAIT
        while not node.navigator.cancels_answered() and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.05)

    # Ctrl-C and SIGTERM are the runner's (a flag), so the context is still alive in the teardown:
    # the running goal is cancelled and the node leaves lockstep. With rclpy's own handlers, a
    # SIGTERM shut the context down first and the process once spun on for an hour.
    try:
        return run_nodes(lambda: [AutonomyNode()], role="autonomy", rclpy_args=args, executor=executor_kind,
                         finished=lambda nodes: 0 if nodes[0].finished else None, before_shutdown=halt)
    except ValueError as error:  # LocationsError, BtLoadError, parameter errors
        print(f"autonomy_node: {error}".replace("\n", " "), file=sys.stderr, flush=True)
        return EXIT_CONFIG


if __name__ == "__main__":
    raise SystemExit(main())
