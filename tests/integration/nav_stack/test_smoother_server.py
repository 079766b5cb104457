"""smoother_server over DDS with a fake global costmap: smooth_path answers, its error codes, the
SmoothPath BT leaf, and the refusal of an unknown plugin type."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import Point32, PolygonStamped
from nav2_msgs.action import SmoothPath
from nav2_msgs.msg import Costmap
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.parameter import Parameter

from nav_stack.core.bt import BehaviorTreeFactory, Blackboard, NodeStatus
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec
from nav_stack.ros.bt_nodes import BtRosContext, register_ros_nodes
from nav_stack.ros.common.conversions import costmap_msg, path_from_array
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.planning.smoother_server import build_nodes, path_poses
from navsuite_testing.nav.world import Harness, get_result, send_goal
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg

pytestmark = pytest.mark.ros

SPEC = GridSpec(100, 60, 0.05, -0.5, -1.5)  # map: x -0.5 .. 4.5, y -1.5 .. 1.5
WALL_X = 3.5  # a lethal wall across x = 3.50 .. 3.55 m
ODOM_IN_MAP = (2.5, -0.5, math.pi / 2)  # odom (a, b) is map (2.5 - b, a - 0.5)


def zigzag(n: int, frame_offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Poses along +x every 5 cm, every other one 1.5 cm to the side (no cusps)."""
    x = np.arange(n) * 0.05 + frame_offset[0]
    y = 0.015 * np.where(np.arange(n) % 2 == 0, 1.0, -1.0) + frame_offset[1]
    return np.column_stack([x, y, np.zeros(n)])


def turning(poses: np.ndarray) -> float:
    d = np.diff(poses[:, :2], axis=0)
    return float(np.abs(np.angle(np.exp(1j * np.diff(np.arctan2(d[:, 1], d[:, 0]))))).sum())


class FakeCostmap(Node):
    """The global costmap's outputs as its node latches them, the robot at the map origin, TF map→odom."""

    def __init__(self, context: Any) -> None:
        super().__init__("fake_global_costmap", context=context)
        costs = np.zeros(SPEC.shape, dtype=np.uint8)
        costs[:, round((WALL_X - SPEC.origin_x) / SPEC.resolution)] = LETHAL_OBSTACLE
        self.costmap_pub = self.create_publisher(Costmap, "global_costmap/costmap_raw", LATCHED)
        self.costmap_pub.publish(costmap_msg(costs, SPEC, "map", Time()))
        self.footprint_pub = self.create_publisher(PolygonStamped, "global_costmap/published_footprint",
                                                   LATCHED)
        footprint = PolygonStamped()
        footprint.header.frame_id = "map"
        footprint.polygon.points = [Point32(x=x, y=y) for x, y in ((0.1, 0.1), (0.1, -0.1), (-0.1, -0.1),
                                                                  (-0.1, 0.1))]
        self.footprint_pub.publish(footprint)
        self.tf_static = StaticTransformBroadcaster(self)
        self.tf_static.send([
            transform_to_msg(Transform.from_xy_yaw(0.0, 0.0, 0.0), "map", "base_link", Time()),
            transform_to_msg(Transform.from_xy_yaw(*ODOM_IN_MAP), "map", "odom", Time())])
        self.smoothed: list[Path] = []
        self.create_subscription(Path, "plan_smoothed", self.smoothed.append, 10)


class Rig:
    def __init__(self, context: Any, overrides: list[Parameter] | None = None) -> None:
        self.harness = Harness(context)
        self.fake = FakeCostmap(context)
        self.server: Any = build_nodes(context=context, parameter_overrides=overrides or [])[0]
        self.harness.add(self.fake, self.server)
        self.harness.bring_up(self.server)
        wait_until(lambda: self.server._grid is not None and self.server._footprint_msg is not None, 20.0,
                   "the costmap and the footprint at the smoother server")
        wait_until(lambda: all(_knows(self.server, "map", child) for child in ("odom", "base_link")), 20.0,
                   "TF map→odom and map→base_link at the smoother server")
        self.client = ActionClient(self.fake, SmoothPath, "smooth_path")

    def smooth(self, poses: np.ndarray, frame: str = "map", smoother_id: str = "",
               check_for_collisions: bool = False) -> tuple[int, Any]:
        goal = SmoothPath.Goal(path=path_from_array(poses, frame, Time()), smoother_id=smoother_id,
                               max_smoothing_duration=Duration(sec=3),
                               check_for_collisions=check_for_collisions)
        return get_result(send_goal(self.client, goal), 30.0)


def _knows(server: Any, target: str, source: str) -> bool:
    try:
        server.frames.frame_pose(target, source)
    except FrameError:
        return False
    return True


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    r: Rig | None = None
    try:
        r = Rig(ros_context)
        yield r
    finally:
        if r is not None:
            r.harness.close()


def test_smooth_path_answers_with_a_smoother_path(rig: Rig) -> None:
    poses = zigzag(41)
    status, result = rig.smooth(poses, check_for_collisions=True)
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
    assert (result.error_code, result.was_completed) == (0, True)
    out = path_poses(result.path)
    assert len(out) == 41 and result.path.header.frame_id == "map"
    np.testing.assert_allclose(out[[0, -1], :2], poses[[0, -1], :2])
    print(f"\nzigzag turning {turning(poses):.2f} rad -> {turning(out):.3f} rad")
    assert turning(out) < 0.2 * turning(poses)
    wait_until(lambda: len(rig.fake.smoothed) == 1, 10.0, "the smoothed path on plan_smoothed")


def test_error_codes_and_the_server_keeps_serving(rig: Rig) -> None:
    status, result = rig.smooth(np.zeros((0, 3)))
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, SmoothPath.Result.INVALID_PATH)
    assert result.error_msg == "the path to smooth is empty"
    status, result = rig.smooth(zigzag(20), smoother_id="curvy")
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, SmoothPath.Result.INVALID_SMOOTHER)
    assert "'curvy'" in result.error_msg and "simple_smoother" in result.error_msg
    status, result = rig.smooth(zigzag(20), frame="nowhere")
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, SmoothPath.Result.INVALID_PATH)
    assert "nowhere" in result.error_msg
    through_wall = zigzag(81)  # reaches x = 4.0, across the wall at 3.5
    status, result = rig.smooth(through_wall, check_for_collisions=True)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED,
                                           SmoothPath.Result.SMOOTHED_PATH_IN_COLLISION)
    assert len(result.path.poses) == 81 and "collides at pose" in result.error_msg
    status, result = rig.smooth(through_wall)  # without the check the same path is fine
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg


def test_a_path_in_another_frame_is_smoothed_in_its_own_frame(rig: Rig) -> None:
    poses = zigzag(41)
    status, in_map = rig.smooth(poses)
    assert status == GoalStatus.STATUS_SUCCEEDED
    status, in_odom = rig.smooth(poses, frame="odom")  # the same shape, elsewhere in the map
    assert status == GoalStatus.STATUS_SUCCEEDED, in_odom.error_msg
    assert in_odom.path.header.frame_id == "odom"
    np.testing.assert_allclose(path_poses(in_odom.path)[:, :2], path_poses(in_map.path)[:, :2], atol=1e-9)
    # 27 poses along odom's -y run along the map's +x from x = 2.5 to 3.8, across the wall; the same
    # numbers in the map frame run down the y axis to y = -1.3, clear of it
    along = zigzag(27)[:, [1, 0, 2]] * [1.0, -1.0, 1.0]
    status, result = rig.smooth(along, frame="odom", check_for_collisions=True)
    assert result.error_code == SmoothPath.Result.SMOOTHED_PATH_IN_COLLISION, result.error_msg
    status, result = rig.smooth(along, check_for_collisions=True)
    assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg


BT_TREE = """
<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <SmoothPath unsmoothed_path="{path}" smoothed_path="{path}" smoother_id="{smoother}"
                was_completed="{completed}" smoothing_duration="{duration}"
                error_code_id="{smoother_error}" error_msg="{smoother_message}"/>
  </BehaviorTree>
</root>
"""


def _run_tree(rig: Rig, path: Path, smoother_id: str) -> tuple[Any, Blackboard]:
    ros = BtRosContext(rig.fake)
    factory = BehaviorTreeFactory()
    register_ros_nodes(factory, ros)
    board = Blackboard()
    for key, value in (("server_timeout", 2000), ("wait_for_service_timeout", 10000), ("path", path),
                       ("smoother", smoother_id)):
        board.set(key, value)
    tree = factory.create_tree_from_text(BT_TREE, blackboard=board,
                                         clock=lambda: rig.fake.get_clock().now().nanoseconds * 1e-9)
    statuses: list[Any] = [NodeStatus.RUNNING]

    def tick() -> None:
        if statuses[-1] is NodeStatus.RUNNING:
            statuses.append(tree.tick_once())

    timer = rig.fake.create_timer(0.05, tick)
    try:
        wait_until(lambda: statuses[-1] is not NodeStatus.RUNNING, 30.0, "the tree to finish")
    finally:
        rig.fake.destroy_timer(timer)
        ros.destroy()
    return statuses[-1], board


def test_the_smooth_path_leaf_smooths_the_trees_path(rig: Rig) -> None:
    plan = path_from_array(zigzag(41), "map", Time())
    status, board = _run_tree(rig, plan, "simple_smoother")
    assert status is NodeStatus.SUCCESS
    smoothed = path_poses(board.get("path"))
    assert turning(smoothed) < 0.2 * turning(path_poses(plan))
    outputs = (board.get("completed"), board.get("smoother_error"), board.get("smoother_message"))
    assert outputs == (True, 0, "")
    assert board.get("duration") >= 0.0
    status, board = _run_tree(rig, plan, "curvy")
    assert status is NodeStatus.FAILURE
    assert board.get("smoother_error") == SmoothPath.Result.INVALID_SMOOTHER
    assert "'curvy'" in board.get("smoother_message")
    assert board.get("path") is plan  # a failed smoothing leaves the plan as it was


def test_an_unknown_plugin_type_fails_configure_naming_it(ros_context: Any) -> None:
    node: Any = build_nodes(context=ros_context, parameter_overrides=[
        Parameter("smoother_plugins", value=["curvy"]),
        Parameter("curvy.plugin", value="nav2_smoother::SavitzkyGolaySmoother")])[0]
    try:
        with pytest.raises(ValueError, match=r"curvy\.plugin 'nav2_smoother::SavitzkyGolaySmoother' is not "
                                             r"one of \['SimpleSmoother'\]"):
            node.configure()
    finally:
        node.destroy_node()
