"""docking_server against sim2d (real nodes over DDS, sim2d's /clock): the failure paths answer with
Nav2's codes and messages, and leave the robot stopped, clear of the dock and untouched.

A 4 × 4 m room with a Create 3 dock; the waffle, the shipped docking_server file
(config/docks/turtlebot3_world.yaml) with the dock moved into the room, in frame odom (sim2d's odom
starts at the spawn and is ideal here; no localization runs). No staging navigation: the robot starts at
the staging pose.

* an unknown dock id: DOCK_NOT_IN_DB at once, the robot never commanded;
* the robot faces away from the dock: FAILED_TO_DETECT_DOCK after initial_perception_timeout;
* a pole dropped in front of the dock hides its tag mid-approach: each retry drives back to the
  staging pose, and after max_retries FAILED_TO_DETECT_DOCK, the robot stopped there, 0.7 m clear;
* a pole dropped beside the line of sight but in the robot's way (the tag stays in view), with a real
  local costmap on sim2d's lidar: the approach's collision check stops the robot short of it, each
  retry backs off to staging and is refused again, FAILED_TO_CONTROL after max_retries naming the
  obstacle; the robot never touches it, and a second goal gets the same answer (the server serves on).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any, cast

import pytest

pytest.importorskip("tf2_msgs.msg")

from action_msgs.msg import GoalStatus
from nav2_msgs.action import DockRobot
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import BatteryState
from std_msgs.msg import UInt32
from visualization_msgs.msg import Marker

from nav_stack.core.costmap import CostmapParams
from nav_stack.core.docking.controller import relative
from nav_stack.core.geometry import Pose2D
from nav_stack.ros.costmap.costmap_ros import CostmapROS
from nav_stack.ros.docking.docking_server import DockingServer, build_nodes
from navsuite_testing.nav.world import Harness, get_result, send_goal, server_args, sim_time_override
from navsuite_testing.ros import REPO, wait_until
from ros_tools.runtime.actions import ActionClient
from sim2d.ros.sim_node import Sim2dNode

pytestmark = pytest.mark.ros

CONTACT = (1.5, 0.0, 0.0)  # the dock's contact pose (map = odom here)
STAGING = (CONTACT[0] - 0.7, 0.0)  # staging_x_offset -0.7
WORLD = f"""name: dock_room
obstacles: [{{type: ring, vertices: [[-2, -2], [2, -2], [2, 2], [-2, 2]], thickness: 0.1}}]
docks: [{{id: home_dock, type: create3_dock, pose: [{CONTACT[0]}, {CONTACT[1]}, {CONTACT[2]}]}}]
"""
DOCK_FILE = REPO / "config" / "docks" / "turtlebot3_world.yaml"
#: m: the waffle's body reaches this far ahead of base_link (the dock file's controller.footprint)
BODY_FRONT = 0.069


class SimDocking:
    """sim2d (waffle at ``start``), docking_server and a probe, spun in the background."""

    def __init__(self, context: Any, world: Path, start: tuple[float, float, float],
                 costmap: bool = False) -> None:
        """``costmap``: also run a local_costmap (nav2_params.yaml's, on sim2d's /scan), so the
        approach's collision check sees obstacles; without it the check has no costmap and is off."""
        self.harness = Harness(context)
        sim_params = {"world": str(world), "robot": "waffle", "real_time_factor": 5.0,
                      "initial_pose.x": start[0], "initial_pose.y": start[1], "initial_pose.yaw": start[2],
                      "odometry.ideal": True}
        self.sim = Sim2dNode(context=context,
                             parameter_overrides=[Parameter(k, value=v) for k, v in sim_params.items()])
        self.probe = Node("docking_sim_probe", context=context)
        self.truth: tuple[float, float, float] | None = None
        self.charging = False
        self.collisions = 0
        self.furthest_x = -math.inf  # the largest base_link x (map) seen: how far the robot went
        self.probe.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        self.probe.create_subscription(BatteryState, "/battery_state", self._on_battery, 10)
        self.probe.create_subscription(UInt32, "/sim2d/collision_count", self._on_collisions, 10)
        self.obstacles = self.probe.create_publisher(Marker, "/sim2d/spawn_obstacle", 10)
        dock = relative(Pose2D(*CONTACT), Pose2D(*start))  # the contact pose in odom
        overrides = {"home_dock.frame": "odom", "home_dock.pose": list(dock), "use_sim_time": True}
        self.server = cast(DockingServer, build_nodes(
            context=context, cli_args=["--ros-args", "--params-file", str(DOCK_FILE)],
            parameter_overrides=[Parameter(k, value=v) for k, v in overrides.items()])[0])
        self.harness.add(self.sim, self.probe, self.server)
        wait_until(lambda: self.truth is not None, 20.0, "sim2d's ground truth")
        self.harness.bring_up(self.server)
        buffer = self.server.frames.listener.buffer
        wait_until(lambda: buffer.can_transform("odom", "base_link"), 20.0, "the robot TF at the server")
        if costmap:
            local = CostmapROS("local_costmap", defaults=CostmapParams.local_defaults(), context=context,
                               cli_args=server_args(), parameter_overrides=sim_time_override())
            self.harness.add(local)
            self.harness.bring_up(local)
            wait_until(local.ready.done, 40.0, "the local costmap's first update")
            wait_until(lambda: self.server.world.obstacles() is not None, 20.0, "the costmap at the server")

    def _on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.truth = (p.x, p.y, 2.0 * math.atan2(q.z, q.w))
        self.furthest_x = max(self.furthest_x, p.x)

    def _on_battery(self, msg: BatteryState) -> None:
        self.charging = msg.power_supply_status == BatteryState.POWER_SUPPLY_STATUS_CHARGING

    def _on_collisions(self, msg: UInt32) -> None:
        self.collisions = msg.data

    def send(self, dock_id: str = "home_dock") -> Any:
        client = ActionClient(self.probe, DockRobot, "dock_robot")
        return send_goal(client, DockRobot.Goal(use_dock_id=True, dock_id=dock_id,
                                                navigate_to_staging_pose=False))

    def distance_to_contact(self) -> float:
        assert self.truth is not None
        return math.hypot(self.truth[0] - CONTACT[0], self.truth[1] - CONTACT[1])

    def drop_pole(self, x: float, y: float, radius: float) -> None:
        marker = Marker(type=Marker.CYLINDER, action=Marker.ADD)
        marker.header.frame_id = "map"
        marker.pose.position.x, marker.pose.position.y = x, y
        marker.scale.x = marker.scale.y = 2.0 * radius
        marker.scale.z = 0.5
        self.obstacles.publish(marker)

    def assert_stopped_clear(self, near: tuple[float, float] | None = None) -> None:
        """Still within 5 s of sim time, not charging, 0.5 m or more from the dock, no collision (and
        within 5 cm of ``near``)."""
        start = self.sim.sim.time
        wait_until(lambda: self.sim.sim.time > start + 1.0, 20.0, "1 s of sim time")  # braking done
        before = self.truth
        wait_until(lambda: self.sim.sim.time > start + 3.0, 20.0, "2 more s of sim time")
        assert before is not None and self.truth is not None
        assert math.hypot(self.truth[0] - before[0], self.truth[1] - before[1]) < 0.002, "still moving"
        assert self.distance_to_contact() > 0.5 and not self.charging and self.collisions == 0
        if near is not None:  # the undock tolerance (0.05 m) and a few mm of braking
            assert math.hypot(self.truth[0] - near[0], self.truth[1] - near[1]) < 0.06, self.truth


@pytest.fixture
def world(tmp_path: Path) -> Path:
    path = tmp_path / "dock_room.yaml"
    path.write_text(WORLD)
    return path


def _close(stack: SimDocking) -> None:
    stack.harness.close()


@pytest.fixture
def facing_away(ros_context: Any, world: Path) -> Iterator[SimDocking]:
    stack = SimDocking(ros_context, world, (STAGING[0], STAGING[1], math.pi))
    try:
        yield stack
    finally:
        _close(stack)


def test_unknown_dock_and_a_dock_out_of_view_fail_with_their_codes(facing_away: SimDocking) -> None:
    stack = facing_away
    start = stack.truth
    status, result = get_result(stack.send("garage"), 30.0)
    assert (status, result.error_code, result.success) == (GoalStatus.STATUS_ABORTED,
                                                            DockRobot.Result.DOCK_NOT_IN_DB, False)
    assert "dock 'garage' is not in the dock database" in result.error_msg

    status, result = get_result(stack.send(), 60.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, DockRobot.Result.FAILED_TO_DETECT_DOCK)
    assert "initial_perception_timeout 5 s" in result.error_msg
    assert "no detected_dock_pose received yet" in result.error_msg
    assert result.num_retries == 0  # Nav2 does not retry the initial perception
    stack.assert_stopped_clear(near=(start[0], start[1]) if start else None)


def test_a_tag_hidden_mid_approach_ends_after_the_retries_with_the_robot_back_at_staging(
        ros_context: Any, world: Path) -> None:
    stack = SimDocking(ros_context, world, (STAGING[0], STAGING[1], 0.0))
    try:
        handle = stack.send()
        wait_until(lambda: stack.truth is not None and stack.truth[0] > STAGING[0] + 0.15, 60.0,
                   "the approach to get under way")
        # a 4 cm pole 0.1 m before the contact pose hides the tag at once; the robot goes on for
        # external_detection_timeout (1 s, 0.15 m) on the last refined pose, well short of the pole
        stack.drop_pole(CONTACT[0] - 0.1, 0.0, 0.02)
        status, result = get_result(handle, 120.0)
        assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED,
                                                DockRobot.Result.FAILED_TO_DETECT_DOCK)
        assert "(all 3 retries used)" in result.error_msg
        assert result.num_retries == 4  # the fourth failure ends it (max_retries 3)
        stack.assert_stopped_clear(near=STAGING)
    finally:
        _close(stack)


def test_an_obstacle_in_the_way_stops_the_approach_short_of_it_and_the_server_serves_on(
        ros_context: Any, world: Path) -> None:
    stack = SimDocking(ros_context, world, (STAGING[0], STAGING[1], 0.0), costmap=True)
    try:
        handle = stack.send()
        wait_until(lambda: stack.truth is not None and stack.truth[0] > STAGING[0] + 0.05, 60.0,
                   "the approach to get under way")
        # a 6 cm pole 0.25 m before the contact pose and 9 cm beside the approach line: the camera still
        # sees the tag past it, the waffle's body (0.133 m half width) would sweep it. Its cells lie
        # outside the last dock_collision_threshold (0.35 m) before the approach target, so they are checked.
        pole = (CONTACT[0] - 0.25, 0.09, 0.03)
        stack.drop_pole(*pole)
        status, result = get_result(handle, 120.0)
        assert (status, result.error_code, result.success) == (GoalStatus.STATUS_ABORTED,
                                                                DockRobot.Result.FAILED_TO_CONTROL, False)
        assert "collision ahead" in result.error_msg and "(all 3 retries used)" in result.error_msg
        assert result.num_retries == 4, result.error_msg  # the fourth failure ends it (max_retries 3)
        # what blocked it: the message names a costmap cell (odom) on the pole, not only a robot pose
        cell = re.search(r"costmap cell at \((\S+), (\S+)\) \(cost 254\)", result.error_msg)
        assert cell is not None and "in 'odom'" in result.error_msg, result.error_msg
        in_odom = relative(Pose2D(pole[0], pole[1], 0.0), Pose2D(STAGING[0], STAGING[1], 0.0))
        off = math.hypot(float(cell.group(1)) - in_odom.x, float(cell.group(2)) - in_odom.y)
        assert off < pole[2] + 0.05, result.error_msg  # the pole's radius and a cell's half diagonal
        print(f"\nfurthest base_link x {stack.furthest_x:.3f} m, pole edge at {pole[0] - pole[2]:.3f} m; "
              f"error_msg: {result.error_msg}")
        assert stack.furthest_x + BODY_FRONT < pole[0] - pole[2] - 0.02  # stopped 2 cm or more short of it
        stack.assert_stopped_clear(near=STAGING)

        # the pole stays (sim2d drops obstacles for good): a new goal is refused the same way, cleanly
        status, result = get_result(stack.send(), 120.0)
        assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, DockRobot.Result.FAILED_TO_CONTROL)
        assert "collision ahead" in result.error_msg and result.num_retries == 4
        stack.assert_stopped_clear(near=STAGING)
    finally:
        _close(stack)
