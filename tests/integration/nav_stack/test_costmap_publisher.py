"""CostmapROS publishes as Nav2's Costmap2DPublisher: one full grid, then the redrawn windows only.

A global costmap on the TB3 map with ``always_send_full_costmap`` false, a static map -> base_link
pose and hand-made scans: a subscriber gets one full ``costmap_raw``, then ``costmap_raw_updates``
whose windows cover a part of the grid, and applying them keeps its copy equal to ``get_costmap``; a
subscriber that joins later gets the current full grid. Without subscribers nothing is converted.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from nav2_msgs.msg import Costmap, CostmapUpdate
from nav2_msgs.srv import GetCostmap
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import LaserScan

from nav_stack.core.costmap.layer import Window
from nav_stack.core.costmap.publish import apply_update
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec
from nav_stack.ros.common.conversions import spec_from_info
from nav_stack.ros.costmap import costmap_publisher
from nav_stack.ros.costmap.costmap_ros import CostmapROS
from navsuite_testing.nav.world import LATCHED, Harness, map_without, server_args
from navsuite_testing.ros import wait_until
from ros_tools.runtime.requests import call_until_answered
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg

pytestmark = pytest.mark.ros
ROBOT = (-2.0, -0.5, 0.0)  # TB3 spawn, in free space; the beams straight ahead meet nothing within 0.6 m


class Probe(Node):
    """Publishes /map, map -> base_link and scans; keeps the raw costmap a subscriber would."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("costmap_publisher_probe", **kwargs)
        self.create_publisher(type(map_without([])), "/map", LATCHED).publish(map_without([]))
        self.tf_static = StaticTransformBroadcaster(self)
        self.tf_static.send([transform_to_msg(Transform.from_xy_yaw(*ROBOT), "map", "base_link",
                                              self.get_clock().now().to_msg())])
        self.scan_pub = self.create_publisher(LaserScan, "/scan", 10)
        self.full: list[Costmap] = []
        self.updates: list[CostmapUpdate] = []
        self.grid: np.ndarray | None = None
        self.spec: GridSpec | None = None
        self.create_subscription(Costmap, "/global_costmap/costmap_raw", self._on_full, LATCHED)
        self.create_subscription(CostmapUpdate, "/global_costmap/costmap_raw_updates", self._on_update,
                                 LATCHED)

    def _on_full(self, msg: Costmap) -> None:
        self.full.append(msg)
        self.spec = spec_from_info(msg.metadata)
        self.grid = np.frombuffer(msg.data, dtype=np.uint8).reshape(self.spec.shape).copy()

    def _on_update(self, msg: CostmapUpdate) -> None:
        self.updates.append(msg)
        if self.grid is not None:
            apply_update(self.grid, msg.x, msg.y, msg.size_x, msg.size_y, msg.data)

    def scan(self, obstacle_range: float) -> None:
        """A 360-beam scan from base_link: beams within ±5° of ahead return at ``obstacle_range``."""
        msg = LaserScan()
        msg.header.frame_id, msg.header.stamp = "base_link", self.get_clock().now().to_msg()
        msg.angle_min, msg.angle_increment = -math.pi, 2.0 * math.pi / 360
        msg.angle_max = msg.angle_min + 359 * msg.angle_increment
        msg.range_min, msg.range_max = 0.12, 3.5
        angles = msg.angle_min + msg.angle_increment * np.arange(360)
        ranges = np.where(np.abs(angles) <= math.radians(5), obstacle_range, np.inf)
        msg.ranges = ranges.astype(np.float32).tolist()
        self.scan_pub.publish(msg)


@pytest.fixture
def rig(ros_context: Any) -> Iterator[tuple[Probe, CostmapROS]]:
    harness = Harness(ros_context)
    try:
        probe = Probe(context=ros_context)
        costmap = CostmapROS("global_costmap", context=ros_context, cli_args=server_args(),
                             parameter_overrides=[Parameter("always_send_full_costmap", value=False)])
        harness.add(probe, costmap)
        harness.bring_up(costmap)
        wait_until(costmap.ready.done, 30.0, "the global costmap's first update")
        yield probe, costmap
    finally:
        harness.close()


def _get_costmap(probe: Probe) -> np.ndarray:
    client = probe.create_client(GetCostmap, "/global_costmap/get_costmap")
    wait_until(client.service_is_ready, 10.0, "get_costmap")
    response = call_until_answered(client, GetCostmap.Request(), 10.0)
    spec = spec_from_info(response.map.metadata)
    return np.frombuffer(response.map.data, dtype=np.uint8).reshape(spec.shape)


def test_one_full_grid_then_windowed_updates_that_rebuild_it(rig: tuple[Probe, CostmapROS]) -> None:
    probe, _ = rig
    wait_until(lambda: probe.grid is not None, 20.0, "the full costmap_raw")
    assert probe.spec is not None
    ahead = (ROBOT[0] + 0.6, ROBOT[1])
    mx, my = probe.spec.world_to_cell(*ahead)
    assert probe.grid is not None and probe.grid[my, mx] != LETHAL_OBSTACLE

    def marked() -> bool:
        probe.scan(0.6)
        return probe.grid is not None and probe.grid[my, mx] == LETHAL_OBSTACLE

    wait_until(marked, 30.0, "an update marking the scan's return")
    assert len(probe.full) == 1, "the full grid went out again without a resize or a new subscriber"
    grid_cells = probe.spec.width * probe.spec.height
    # a scan clears up to 3 m around the robot: its window (plus inflation) is a part of the 9 x 7.8 m map
    assert any(u.size_x * u.size_y < grid_cells * 3 // 4 for u in probe.updates), "updates carry all cells"
    wait_until(lambda: np.array_equal(probe.grid, _get_costmap(probe)), 20.0,  # type: ignore[arg-type]
               "the full grid plus the updates to equal get_costmap")

    late: list[Costmap] = []
    probe.create_subscription(Costmap, "/global_costmap/costmap_raw", late.append, LATCHED)
    shape = probe.spec.shape

    def late_grid_current() -> bool:
        grids = (np.frombuffer(m.data, dtype=np.uint8).reshape(shape) for m in late)
        return any(grid[my, mx] == LETHAL_OBSTACLE for grid in grids)

    wait_until(late_grid_current, 20.0, "a full grid, current, for the late subscriber")


class _Publisher:
    def __init__(self, subscribers: int) -> None:
        self.subscribers, self.sent = subscribers, 0

    def get_subscription_count(self) -> int:
        return self.subscribers


class _Node:
    """Just what CostmapPublisher asks of its node; every topic has ``subscribers`` subscribers."""

    def __init__(self, subscribers: int, ros_node: Node) -> None:
        self.subscribers, self.ros_node = subscribers, ros_node

    def create_publisher(self, *_: Any) -> _Publisher:
        return _Publisher(self.subscribers)

    def get_clock(self) -> Any:
        return self.ros_node.get_clock()


def test_nothing_is_converted_without_subscribers(ros_context: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    node = Node("costmap_publisher_unit", context=ros_context)
    try:
        costs, spec = np.zeros((30, 40), dtype=np.uint8), GridSpec(40, 30, 0.05)
        watched = costmap_publisher.CostmapPublisher(_Node(1, node), "map", False)  # type: ignore[arg-type]
        assert [type(m).__name__ for _, m in watched.prepare(costs, spec)] == ["OccupancyGrid", "Costmap"]
        watched.add_window(Window(1, 2, 4, 6))
        sent = watched.prepare(costs, spec)
        assert sorted(type(m).__name__ for _, m in sent) == sorted(
            ["CostmapUpdate"] + (["OccupancyGridUpdate"] if costmap_publisher.OccupancyGridUpdate else []))
        assert all((m.x, m.y) == (1, 2) and len(m.data) == 12 for _, m in sent)

        def no_conversion(_: Any) -> Any:
            raise AssertionError("converted costs that nobody subscribes to")

        monkeypatch.setattr(costmap_publisher, "occupancy_of", no_conversion)
        unwatched = costmap_publisher.CostmapPublisher(_Node(0, node), "map", True)  # type: ignore[arg-type]
        unwatched.add_window(Window(1, 2, 4, 6))
        assert unwatched.prepare(costs, spec) == [] and unwatched.prepare(costs, spec) == []
    finally:
        node.destroy_node()
