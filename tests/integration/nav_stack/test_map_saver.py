"""map_saver: save_map service and map_saver_cli round trips, overwrite protection, bad formats."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node

from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import load_map
from nav_stack.ros.conversions import occupancy_msg
from nav_stack.ros.map_saver import MapSaver
from nav_stack.ros.qos import LATCHED
from tests.helpers.nav_ros_loc_nodes import MAP_YAML, call
from tests.helpers.ros import start_python, stop_process, wait_until

pytestmark = pytest.mark.ros


class Graph:
    def __init__(self, context: Any) -> None:
        self.saver = MapSaver(context=context)
        self.probe = Node("saver_probe", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.saver)
        self.executor.add_node(self.probe)
        self.map_pub = self.probe.create_publisher(OccupancyGrid, "/map", LATCHED)
        self.client = self.probe.create_client(SaveMap, "/map_saver/save_map")
        assert self.saver.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert self.saver.trigger_activate() == TransitionCallbackReturn.SUCCESS

    def publish(self, data: np.ndarray, spec: GridSpec) -> None:
        self.map_pub.publish(occupancy_msg(data, spec, "map", self.probe.get_clock().now().to_msg()))

    def save(self, **fields: Any) -> bool:
        return bool(call(self.executor, self.client, SaveMap.Request(**fields)).result)


@pytest.fixture
def graph(ros_context: Any) -> Iterator[Graph]:
    g = Graph(ros_context)
    try:
        yield g
    finally:
        g.executor.shutdown()
        g.saver.destroy_node()
        g.probe.destroy_node()


def test_trinary_round_trip_keeps_occupied_free_and_unknown(graph: Graph, tmp_path: Path) -> None:
    original = load_map(MAP_YAML)
    assert {-1, 0, 100} == set(np.unique(original.data).tolist())
    graph.publish(original.data, original.spec)
    assert graph.save(map_url=str(tmp_path / "saved"))  # Nav2 defaults: free 0.25, occupied 0.65
    reloaded = load_map(tmp_path / "saved.yaml")
    np.testing.assert_array_equal(reloaded.data, original.data)
    assert reloaded.spec == original.spec


def test_raw_round_trip_is_exact_for_every_value(graph: Graph, tmp_path: Path) -> None:
    spec = GridSpec(17, 7, 0.1, -1.0, 2.0)
    data = (np.arange(spec.width * spec.height) % 102 - 1).reshape(spec.shape).astype(np.int8)  # -1..100
    graph.publish(data, spec)
    assert graph.save(map_url=str(tmp_path / "raw"), map_mode="raw")
    np.testing.assert_array_equal(load_map(tmp_path / "raw.yaml").data, data)


def test_service_refuses_overwrite_and_unknown_formats(graph: Graph, tmp_path: Path) -> None:
    original = load_map(MAP_YAML)
    graph.publish(original.data, original.spec)
    assert graph.save(map_url=str(tmp_path / "once"))
    before = (tmp_path / "once.pgm").read_bytes()
    graph.publish(np.zeros_like(original.data), original.spec)
    assert not graph.save(map_url=str(tmp_path / "once"))
    assert (tmp_path / "once.pgm").read_bytes() == before
    assert not graph.save(map_url=str(tmp_path / "png"), image_format="png")
    assert not graph.save(map_url=str(tmp_path / "mode"), map_mode="fancy")
    assert not (tmp_path / "png.pgm").exists() and not (tmp_path / "mode.pgm").exists()


def test_cli_saves_then_refuses_to_overwrite(ros_context: Any, tmp_path: Path) -> None:
    original = load_map(MAP_YAML)
    node = Node("cli_map_pub", context=ros_context)
    pub = node.create_publisher(OccupancyGrid, "/map", LATCHED)
    pub.publish(occupancy_msg(original.data, original.spec, "map", node.get_clock().now().to_msg()))
    base = tmp_path / "my_map"
    try:
        proc = start_python("nav_stack.ros.map_saver", ["-f", str(base), "--occ", "0.65", "--free", "0.25"])
        executor = SingleThreadedExecutor(context=ros_context)
        executor.add_node(node)
        wait_until(lambda: (executor.spin_once(timeout_sec=0.05), proc.poll())[1] is not None, 60.0,
                   "map_saver_cli to finish")
        assert proc.returncode == 0, stop_process(proc)
        np.testing.assert_array_equal(load_map(base.with_suffix(".yaml")).data, original.data)

        again = start_python("nav_stack.ros.map_saver", ["-f", str(base)])
        output = stop_process(again, timeout=30.0) if again.wait(timeout=30.0) is not None else ""
        assert again.returncode == 2
        assert output.strip().splitlines() == [
            f"map_saver_cli: error: {base}.pgm exists; refusing to overwrite it (use --overwrite)"]

        bad = start_python("nav_stack.ros.map_saver", ["-f", str(tmp_path / "other"), "--fmt", "png"])
        bad.wait(timeout=30.0)
        assert bad.returncode == 2 and "image_format 'png' is not supported" in stop_process(bad)
    finally:
        executor.shutdown()
        node.destroy_node()
