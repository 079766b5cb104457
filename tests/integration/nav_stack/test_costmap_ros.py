"""CostmapROS nodes on sim2d: topics and QoS, map pillars, scan marking, clear_entirely and get_costmap."""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from nav2_msgs.msg import Costmap
from nav2_msgs.srv import ClearEntireCostmap, GetCostmap
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
from std_srvs.srv import SetBool

from nav_stack.core.costmap import CostmapParams
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from nav_stack.ros.common.conversions import spec_from_info
from nav_stack.ros.costmap.costmap_ros import CostmapROS
from navsuite_testing.nav.world import (
    LATCHED,
    Harness,
    WorldNode,
    server_args,
    sim_time_override,
    start_sim,
    stop_process,
)
from navsuite_testing.ros import wait_until

pytestmark = pytest.mark.ros
MISSING_PILLAR = (-1.1, 0.0)  # cut out of the map; the sim still has it, 1 m ahead-left of the spawn


@pytest.fixture(scope="module")
def sim() -> Iterator[subprocess.Popen[str]]:
    proc = start_sim(rtf=3.0)
    try:
        yield proc
    finally:
        stop_process(proc)


@pytest.fixture
def costmaps(
    ros_context: Any, sim: subprocess.Popen[str]
) -> Iterator[tuple[Node, CostmapROS, CostmapROS]]:
    harness = Harness(ros_context)
    try:
        world = WorldNode(removed_pillars=[MISSING_PILLAR], context=ros_context)
        probe = Node("costmap_probe", context=ros_context)
        common = {"context": ros_context, "cli_args": server_args(),
                  "parameter_overrides": sim_time_override()}
        global_costmap = CostmapROS("global_costmap", **common)
        local_costmap = CostmapROS("local_costmap", defaults=CostmapParams.local_defaults(), **common)
        harness.add(world, probe, global_costmap, local_costmap)
        wait_until(lambda: world.truth is not None, 20.0, "sim2d ground truth")
        world.reset_sim()
        for node in (global_costmap, local_costmap):
            harness.bring_up(node)
            wait_until(node.ready.done, 40.0, f"{node.get_name()} never updated")
        probe.world = world  # type: ignore[attr-defined]
        yield probe, global_costmap, local_costmap
    finally:
        harness.close()


def cost_at(grid: OccupancyGrid | Costmap, x: float, y: float) -> int:
    info = grid.info if isinstance(grid, OccupancyGrid) else grid.metadata
    spec = spec_from_info(info)
    dtype = np.int8 if isinstance(grid, OccupancyGrid) else np.uint8
    data = np.frombuffer(grid.data, dtype=dtype).reshape(spec.shape)
    mx, my = spec.world_to_cell(x, y)
    return int(data[my, mx])


def latest(probe: Node, msg_type: Any, topic: str) -> Any:
    """The newest message on ``topic`` (waits for the first one).

    One subscription per topic and probe, kept for the whole test: the polling loops below call this
    many times, and a new subscription per call had to be discovered again each time, which in
    loaded full-suite runs took over 20 s.
    """
    newest: dict[str, Any] = probe.__dict__.setdefault("newest_messages", {})
    if topic not in newest:
        newest[topic] = None
        probe.create_subscription(msg_type, topic, lambda msg: newest.__setitem__(topic, msg), LATCHED)
    wait_until(lambda: newest[topic] is not None, 30.0, f"a message on {topic}")
    return newest[topic]


def test_topics_types_and_qos(costmaps: Any) -> None:
    probe, _, _ = costmaps
    expected = {"costmap": "nav_msgs/msg/OccupancyGrid", "costmap_raw": "nav2_msgs/msg/Costmap",
                "published_footprint": "geometry_msgs/msg/PolygonStamped"}
    for name in ("global_costmap", "local_costmap"):
        for topic, type_name in expected.items():
            infos = probe.get_publishers_info_by_topic(f"/{name}/{topic}")
            assert len(infos) == 1, f"/{name}/{topic} has {len(infos)} publishers"
            qos = infos[0].qos_profile
            assert infos[0].topic_type == type_name
            # (the graph does not report the history depth)
            assert qos.reliability == ReliabilityPolicy.RELIABLE
            assert qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
    grid = latest(probe, OccupancyGrid, "/local_costmap/costmap")
    assert grid.header.frame_id == "odom"
    assert (grid.info.width, grid.info.height) == (60, 60)
    raw = latest(probe, Costmap, "/global_costmap/costmap_raw")
    assert raw.header.frame_id == "map"


def test_pillars_are_lethal_and_inflated_and_the_missing_one_is_seen(costmaps: Any) -> None:
    probe, _, _ = costmaps
    grid = latest(probe, OccupancyGrid, "/global_costmap/costmap")
    assert cost_at(grid, 0.0, 0.0) == 100  # pillar centre: lethal
    assert cost_at(grid, 0.0, 0.30) == 99  # 0.15 m from its edge, inside the 0.23 m inscribed radius
    assert 1 <= cost_at(grid, 0.0, 0.6) < 99  # inflated
    # The pillar cut out of the map is marked from the scan in both costmaps (its face at x = -1.25).
    raw = latest(probe, Costmap, "/global_costmap/costmap_raw")
    wait_until(lambda: cost_at(latest(probe, Costmap, "/global_costmap/costmap_raw"), -1.24, 0.0)
               == LETHAL_OBSTACLE, 20.0, "the scan to mark the missing pillar (global)")
    assert cost_at(raw, -1.1, 0.45) < INSCRIBED_INFLATED_OBSTACLE
    # odom's origin is the spawn pose (-2.0, -0.5): the pillar face is at odom (0.76, 0.5).
    wait_until(lambda: cost_at(latest(probe, Costmap, "/local_costmap/costmap_raw"), 0.76, 0.5)
               == LETHAL_OBSTACLE, 20.0, "the scan to mark the missing pillar (local)")


def test_clear_entirely_and_get_costmap(costmaps: Any) -> None:
    probe, global_costmap, _ = costmaps
    get = probe.create_client(GetCostmap, "/global_costmap/get_costmap")
    clear = probe.create_client(ClearEntireCostmap, "/global_costmap/clear_entirely_global_costmap")
    pause = probe.create_client(SetBool, "/sim2d/pause")
    world = probe.world  # type: ignore[attr-defined]
    response = world.call(get, GetCostmap.Request())
    assert (response.map.metadata.size_x, response.map.metadata.size_y) == (180, 156)
    assert len(response.map.data) == 180 * 156
    wait_until(lambda: cost_at(world.call(get, GetCostmap.Request()).map, -1.24, 0.0) == LETHAL_OBSTACLE,
               20.0, "the scan to mark the missing pillar")
    world.call(pause, SetBool.Request(data=True))  # no scans, no clock: nothing re-marks it
    try:
        world.call(clear, ClearEntireCostmap.Request())
        cleared = world.call(get, GetCostmap.Request()).map
        assert cost_at(cleared, -1.24, 0.0) < INSCRIBED_INFLATED_OBSTACLE, "the scan obstacle survived"
        assert cost_at(cleared, 0.0, 0.0) == LETHAL_OBSTACLE, "the static map was lost"
        assert not global_costmap.current, "no scan since the clear: a controller must not trust it"
    finally:
        world.call(pause, SetBool.Request(data=False))
    wait_until(lambda: global_costmap.current, 20.0, "an update drawing a scan received after the clear")
    wait_until(lambda: cost_at(world.call(get, GetCostmap.Request()).map, -1.24, 0.0) == LETHAL_OBSTACLE,
               20.0, "the scan to mark the pillar again")
