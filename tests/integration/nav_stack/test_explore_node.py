"""nav-explore's ending: the final save is a coroutine on the node's executor, never a blocking wait.

The run is ended directly (``_finish``) with a map received on /map, so the test needs no SLAM and no
Nav2 stack: with a map_saver the map goes through its ``map_saver/save_map`` service, without one
explore writes it itself after SAVER_DISCOVERY. Meanwhile the executor keeps delivering messages.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from nav_msgs.msg import OccupancyGrid
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import String

from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import load_map
from nav_stack.ros.common.conversions import occupancy_msg
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.slam.explore import ExploreNode
from nav_stack.ros.slam.map_saver import MapSaver
from navsuite_testing.ros import spin_until
from ros_tools.runtime.executor import make_executor

pytestmark = pytest.mark.ros

SPEC = GridSpec(12, 8, 0.05, -0.3, -0.2)


def _map() -> np.ndarray:
    data = np.full(SPEC.shape, -1, dtype=np.int8)
    data[2:6, 2:10] = 0
    data[1, :] = 100
    return data


@pytest.mark.parametrize("executor_kind", ["events", "single"])
@pytest.mark.parametrize("with_saver", [True, False])
def test_the_run_ends_by_saving_the_map_without_blocking(ros_context: Any, tmp_path: Path, capfd: Any,
                                                         executor_kind: str, with_saver: bool) -> None:
    executor = make_executor(executor_kind, ros_context)
    explore = ExploreNode(str(tmp_path / "explored"), context=ros_context,
                          parameter_overrides=[Parameter("use_sim_time", value=False)])
    probe = Node("explore_probe", context=ros_context)
    nodes: list[Any] = [explore, probe]
    if with_saver:
        saver = MapSaver(context=ros_context)
        nodes.append(saver)
        assert saver.trigger_configure() == TransitionCallbackReturn.SUCCESS
    for node in nodes:
        executor.add_node(node)
    chatter: list[str] = []
    probe.create_subscription(String, "/explore_test_chatter", lambda m: chatter.append(m.data), 10)
    chatter_pub = probe.create_publisher(String, "/explore_test_chatter", 10)
    map_pub = probe.create_publisher(OccupancyGrid, "/map", LATCHED)
    try:
        map_pub.publish(occupancy_msg(_map(), SPEC, "map", probe.get_clock().now().to_msg()))
        spin_until(executor, lambda: explore.map is not None, 10.0, "explore's /map")
        explore._finish("test over", 0)
        assert not explore.finished, "finished before the map was saved"
        sent = 0
        while not explore.finished:  # the executor keeps serving other callbacks during the save
            chatter_pub.publish(String(data=str(sent)))
            sent += 1
            spin_until(executor, lambda n=sent: len(chatter) >= n or explore.finished, 30.0, "the chatter")
        assert explore.exit_code == 0
        assert len(chatter) >= 1
        said = capfd.readouterr().out
        assert ("map saved to" in said) and (("(map_saver)" in said) == with_saver), said
        saved = load_map(tmp_path / "explored.yaml")
        assert saved.spec == SPEC
        np.testing.assert_array_equal(saved.data, _map())
        assert not list(explore.clients), "the save left its service client behind"
    finally:
        executor.shutdown()
        for node in nodes:
            node.destroy_node()
