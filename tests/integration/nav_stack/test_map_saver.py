"""map_saver: save_map service and map_saver_cli round trips, overwrite protection, bad formats.

The service tests run on both executors (the EventsExecutor cannot await a service callback itself;
map_saver.serve_deferred answers later), and one checks that a save waiting for its map blocks nothing.
"""

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
from nav_stack.ros.common.conversions import occupancy_msg
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.slam.map_saver import MapSaver
from navsuite_testing.localization.nodes import MAP_YAML, call
from navsuite_testing.ros import spin_until, start_python, stop_process, wait_until
from ros_tools.runtime.executor import make_executor

pytestmark = pytest.mark.ros


class Graph:
    def __init__(self, context: Any, executor: str) -> None:
        self.saver = MapSaver(context=context)
        self.probe = Node("saver_probe", context=context)
        self.executor = make_executor(executor, context)
        self.executor.add_node(self.saver)
        self.executor.add_node(self.probe)
        self.map_pub = self.probe.create_publisher(OccupancyGrid, "/map", LATCHED)
        self.client = self.probe.create_client(SaveMap, "/map_saver/save_map")
        assert self.saver.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert self.saver.trigger_activate() == TransitionCallbackReturn.SUCCESS

    def publish(self, data: np.ndarray, spec: GridSpec) -> None:
        self.map_pub.publish(occupancy_msg(data, spec, "map", self.probe.get_clock().now().to_msg()))

    def save(self, **fields: Any) -> bool:
        # Sent once: a second copy would find the file the first wrote, or wait again for the map.
        return bool(call(self.executor, self.client, SaveMap.Request(**fields), resend_after=None).result)


@pytest.fixture(params=["events", "single"])
def graph(ros_context: Any, request: Any) -> Iterator[Graph]:
    g = Graph(ros_context, request.param)
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


def test_a_save_waiting_for_its_map_blocks_no_callback(graph: Graph, tmp_path: Path) -> None:
    """The map arrives only after the request: meanwhile the same executor keeps serving the saver's
    lifecycle service and the probe's subscriptions, then the save succeeds with that map."""
    from lifecycle_msgs.srv import GetState

    spec = GridSpec(9, 5, 0.05, 0.0, 0.0)
    data = np.zeros(spec.shape, dtype=np.int8)
    spin_until(graph.executor, graph.client.service_is_ready, 10.0, "the save_map service")
    timers = len(list(graph.saver.timers))  # the bond heartbeat
    late_pub = graph.probe.create_publisher(OccupancyGrid, "/late_map", LATCHED)
    pending = graph.client.call_async(SaveMap.Request(map_url=str(tmp_path / "late"), map_topic="/late_map"))
    get_state = graph.probe.create_client(GetState, "/map_saver/get_state")
    state = call(graph.executor, get_state, GetState.Request())
    assert state.current_state.label == "active" and not pending.done()
    late_pub.publish(occupancy_msg(data, spec, "map", graph.probe.get_clock().now().to_msg()))
    spin_until(graph.executor, pending.done, 10.0, "the answer of the waiting save")
    assert pending.result().result
    assert load_map(tmp_path / "late.yaml").spec == spec
    # Nobody publishes: the timeout timer (save_map_timeout, 2 s steady) answers, and cleans up.
    assert not graph.save(map_url=str(tmp_path / "never"), map_topic="/nobody_publishes_this")
    assert not (tmp_path / "never.pgm").exists()
    assert len(list(graph.saver.timers)) == timers and all(sub.topic_name != "/nobody_publishes_this"
                                                for sub in graph.saver.subscriptions)


def test_cli_saves_then_refuses_to_overwrite(ros_context: Any, tmp_path: Path) -> None:
    original = load_map(MAP_YAML)
    node = Node("cli_map_pub", context=ros_context)
    pub = node.create_publisher(OccupancyGrid, "/map", LATCHED)
    pub.publish(occupancy_msg(original.data, original.spec, "map", node.get_clock().now().to_msg()))
    base = tmp_path / "my_map"
    try:
        proc = start_python("nav_stack.ros.slam.map_saver",
                            ["-f", str(base), "--occ", "0.65", "--free", "0.25"])
        executor = SingleThreadedExecutor(context=ros_context)
        executor.add_node(node)
        wait_until(lambda: (executor.spin_once(timeout_sec=0.05), proc.poll())[1] is not None, 60.0,
                   "map_saver_cli to finish")
        assert proc.returncode == 0, stop_process(proc)
        np.testing.assert_array_equal(load_map(base.with_suffix(".yaml")).data, original.data)

        again = start_python("nav_stack.ros.slam.map_saver", ["-f", str(base)])
        output = stop_process(again, timeout=30.0) if again.wait(timeout=30.0) is not None else ""
        assert again.returncode == 2
        assert output.strip().splitlines() == [
            f"map_saver_cli: error: {base}.pgm exists; refusing to overwrite it (use --overwrite)"]

        bad = start_python("nav_stack.ros.slam.map_saver", ["-f", str(tmp_path / "other"), "--fmt", "png"])
        bad.wait(timeout=30.0)
        assert bad.returncode == 2 and "image_format 'png' is not supported" in stop_process(bad)
    finally:
        executor.shutdown()
        node.destroy_node()
