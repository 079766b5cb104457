"""map_server node: /map equals the file, GetMap, LoadMap with every result code, configure errors."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from lifecycle_msgs.msg import State
from nav2_msgs.srv import LoadMap
from nav_msgs.msg import OccupancyGrid
from nav_msgs.srv import GetMap
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter as RclParameter

from nav_stack.core.map_io import load_map
from nav_stack.ros.common.conversions import grid_from_occupancy
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.localization.map_server import MapServer
from navsuite_testing.localization.nodes import MAP_YAML, call, write_map_yaml
from navsuite_testing.ros import spin_until

pytestmark = pytest.mark.ros


@pytest.fixture
def yaml_filename() -> str:
    return str(MAP_YAML)


@pytest.fixture
def graph(ros_context: Any, yaml_filename: str) -> Iterator[tuple[SingleThreadedExecutor, MapServer, Node]]:
    server = MapServer(context=ros_context,
                       parameter_overrides=[RclParameter("yaml_filename", value=yaml_filename)])
    probe = Node("map_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(server)
    executor.add_node(probe)
    try:
        yield executor, server, probe
    finally:
        executor.shutdown()
        server.destroy_node()
        probe.destroy_node()


def _start(server: MapServer) -> None:
    assert server.trigger_configure() == TransitionCallbackReturn.SUCCESS
    assert server.trigger_activate() == TransitionCallbackReturn.SUCCESS


def _grid(msg: OccupancyGrid) -> np.ndarray:
    return grid_from_occupancy(msg)[0]


def test_map_topic_equals_the_file_and_reaches_a_late_subscriber(graph: Any) -> None:
    executor, server, probe = graph
    _start(server)
    received: list[OccupancyGrid] = []
    probe.create_subscription(OccupancyGrid, "/map", received.append, LATCHED)  # joins after publication
    spin_until(executor, lambda: bool(received), 10.0, "the latched /map")
    expected = load_map(MAP_YAML)
    data, spec = grid_from_occupancy(received[0])
    assert received[0].header.frame_id == "map"
    assert spec.width == expected.spec.width and spec.height == expected.spec.height
    assert spec.resolution == pytest.approx(0.05)
    assert (spec.origin_x, spec.origin_y) == pytest.approx((expected.spec.origin_x, expected.spec.origin_y))
    np.testing.assert_array_equal(data, expected.data)


def test_get_map_and_load_map_codes_keep_the_old_map(graph: Any, tmp_path: Path) -> None:
    executor, server, probe = graph
    _start(server)
    get_map = probe.create_client(GetMap, "/map_server/map")
    load = probe.create_client(LoadMap, "/map_server/load_map")
    original = load_map(MAP_YAML).data
    np.testing.assert_array_equal(_grid(call(executor, get_map, GetMap.Request()).map), original)

    shifted = write_map_yaml(tmp_path / "shifted.yaml", origin=[-1.0, -2.0, 0.0])
    response = call(executor, load, LoadMap.Request(map_url=f"file://{shifted}"))
    assert response.result == LoadMap.Response.RESULT_SUCCESS
    assert response.map.info.origin.position.x == pytest.approx(-1.0)
    assert call(executor, get_map, GetMap.Request()).map.info.origin.position.y == pytest.approx(-2.0)

    bad_meta = write_map_yaml(tmp_path / "no_resolution.yaml", resolution=None)
    bad_image = tmp_path / "bad.pgm"
    bad_image.write_bytes(b"\x89PNG not a pgm")
    bad_data = write_map_yaml(tmp_path / "bad_data.yaml", image=str(bad_image))
    cases = [
        (str(tmp_path / "missing.yaml"), LoadMap.Response.RESULT_MAP_DOES_NOT_EXIST),
        ("package://tb3/maps/x.yaml", LoadMap.Response.RESULT_MAP_DOES_NOT_EXIST),
        (str(bad_meta), LoadMap.Response.RESULT_INVALID_MAP_METADATA),
        (f"file://{bad_data}", LoadMap.Response.RESULT_INVALID_MAP_DATA),
    ]
    for url, code in cases:
        assert call(executor, load, LoadMap.Request(map_url=url)).result == code, url
        kept = call(executor, get_map, GetMap.Request()).map
        assert kept.info.origin.position.x == pytest.approx(-1.0), url  # still the shifted map
        np.testing.assert_array_equal(_grid(kept), original)

    assert server.trigger_deactivate() == TransitionCallbackReturn.SUCCESS
    response = call(executor, load, LoadMap.Request(map_url=str(MAP_YAML)))
    assert response.result == LoadMap.Response.RESULT_UNDEFINED_FAILURE  # only served while active


@pytest.mark.parametrize("yaml_filename", ["/nonexistent/broken.yaml"])
def test_bad_yaml_filename_fails_configure_and_the_node_recovers(graph: Any) -> None:
    executor, server, probe = graph
    assert server.trigger_configure() == TransitionCallbackReturn.FAILURE
    assert server._state_machine.current_state[0] == State.PRIMARY_STATE_UNCONFIGURED
    server.set_parameters([RclParameter("yaml_filename", value=str(MAP_YAML))])
    _start(server)
    response = call(executor, probe.create_client(GetMap, "/map_server/map"), GetMap.Request())
    assert response.map.info.width == load_map(MAP_YAML).spec.width
