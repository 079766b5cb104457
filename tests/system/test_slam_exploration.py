"""SLAM system run (seed 001): explore turtlebot3_world without a human, save the map, navigate on it.

Phase 1: sim2d (default drifting odometry) + the SLAM processes of ``nav-bringup --slam``
(nav_stack.ros.slam_bringup) + the Nav2 servers; ``nav-explore -f <map>`` drives NavigateToPose goals
from the seeds' spawn (-2.0, -0.5, 0) until no reachable frontier is left, then saves the map.

Map check: the reference maps/turtlebot3_world.yaml also marks the solid blocks' interiors and
cells outside the wall, which no lidar inside the arena can see. So the truth is restricted to the
*observable* occupied cells: those 8-adjacent to the reference's free space connected to the spawn
(tests/helpers/nav_ros_slam_stack.observable_walls). The SLAM map's occupied cells are compared
with them by IoU with a one-cell tolerance (TP: estimate cells within a cell of the truth; FP: other
estimate cells; FN: truth cells farther than a cell from any estimate cell); it must reach 0.8. The
map frame is checked at the same time: map_start_pose puts it on the reference's frame, so a frame
error shows up as a low IoU. The SLAM pose (slam/pose) must stay near the ground truth (the
bounds of tests/helpers/nav_ros_slam_drive.py).

Phase 2 (seed: "navigation on the saved map"): the saved map round-trips through map_server, amcl
starts at the spawn, and three NavigateToPose goals succeed in a row (issue 20: navigate to 3 goals
on the saved map): Nav2's system-test goal (0.0, 2.0), then the world's east spawn (1.9, 0.0) and back
to the seeds' spawn (-2.0, -0.5), legs that cross or round the pillar field. The
stack runs as ``nav-bringup --map`` runs it: every Nav2 node in one process.

Both phases run sim2d in lockstep with the stack's processes at SYSTEM_RTF (``max`` by default).
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav_stack.ros.planner_server", reason="the Nav2 servers do not exist yet")
pytest.importorskip("nav_stack.ros.bt_navigator", reason="the Nav2 servers do not exist yet")
pytest.importorskip("nav_stack.ros.map_saver", reason="map_saver does not exist yet")

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PointStamped, PoseWithCovarianceStamped
from nav2_msgs.action import NavigateToPose
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import UInt32

from nav_stack.core.map_io import load_map
from nav_stack.ros.conversions import pose_stamped
from nav_stack.ros.qos import LATCHED
from nav_stack.ros.slam_bringup import slam_processes
from ros_tools.runtime.actions import ActionClient, send_until_acknowledged
from ros_tools.runtime.lockstep import LockstepParticipant
from ros_tools.tf.ros import TransformListener
from tests.helpers.nav_ros_slam_drive import SLAM_MAX_ERROR, SLAM_MAX_MEDIAN_ERROR
from tests.helpers.nav_ros_slam_stack import (
    NAV_SERVERS,
    PARAMS_FILE,
    Stack,
    compare_with_reference,
    explore,
    nav_specs,
    progress_numbers,
    saved_map_specs,
    sim_spec,
)
from tests.helpers.ros import SYSTEM_RTF, BackgroundSpin, wait_until

pytestmark = [pytest.mark.slow, pytest.mark.ros]
#: The processes the simulator waits for in lockstep (their run_nodes roles, and this test's probe).
PROBE_ROLE = "slam_system_probe"
SLAM_ROLES = ("slam", *NAV_SERVERS, PROBE_ROLE)
SAVED_MAP_ROLES = ("nav2", PROBE_ROLE)  # phase 2: the one-process stack, as nav-bringup runs it
#: Phase 2's goals (x, y, yaw; map frame): spawns of sim2d/worlds/turtlebot3_world.yaml, so free.
GOALS = ((0.0, 2.0, 0.0), (1.9, 0.0, math.pi), (-2.0, -0.5, 0.0))
#: Exploring takes 90-150 sim s here; the limits end a stuck run with the explorer's log.
EXPLORE_SIM_S, EXPLORE_WALL_S = 300.0, 360.0


class Probe:
    """Ground truth vs slam/pose (errors), collision count, and a NavigateToPose client; spun in a thread."""

    def __init__(self, context: Any) -> None:
        self.node = Node("slam_system_probe", context=context)
        self.truth: tuple[float, float, float] | None = None  # t, x, y
        self._recent_truth: deque[tuple[float, float, float]] = deque(maxlen=400)  # ~13 s at 30 Hz
        self.errors: list[float] = []
        self.collisions: list[int] = []
        self.contacts: list[str] = []  # where each new collision happened, for the failure message
        self.node.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        self.node.create_subscription(PoseWithCovarianceStamped, "/slam/pose", self._on_pose, LATCHED)
        self.node.create_subscription(UInt32, "/sim2d/collision_count",
                                      lambda m: self.collisions.append(m.data), LATCHED)
        self.node.create_subscription(PointStamped, "/sim2d/collisions", self._on_contact, 10)
        self.amcl_poses: list[PoseWithCovarianceStamped] = []
        self.node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", self.amcl_poses.append,
                                      LATCHED)
        self.navigate = ActionClient(self.node, NavigateToPose, "navigate_to_pose")
        # In lockstep, so that it sees every ground-truth pose however loaded the machine is.
        self.lockstep = LockstepParticipant(self.node, PROBE_ROLE)
        # Made before the executor spins, destroyed after: a subscription destroyed while another
        # thread builds its wait set kills that thread (rclpy's InvalidHandle).
        self.tf = TransformListener(self.node)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self._spin = BackgroundSpin(self.executor, "slam probe")

    def _on_truth(self, msg: Odometry) -> None:
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        self.truth = (stamp, msg.pose.pose.position.x, msg.pose.pose.position.y)
        self._recent_truth.append(self.truth)

    def truth_at(self, stamp: float) -> tuple[float, float] | None:
        """Ground-truth position (m) at ``stamp`` (sim s), interpolated; None outside what was received.

        The SLAM pose is stamped with its scan, and arrives after the scan is processed, when the
        newest ground truth is already later: comparing with that one would add up to 0.26 m/s times
        the gap to the error being measured.
        """
        for (t0, x0, y0), (t1, x1, y1) in itertools.pairwise(list(self._recent_truth)):
            if t0 <= stamp <= t1:
                k = (stamp - t0) / (t1 - t0) if t1 > t0 else 0.0
                return x0 + k * (x1 - x0), y0 + k * (y1 - y0)
        return None

    def _on_contact(self, msg: PointStamped) -> None:
        robot = "unknown" if self.truth is None else f"({self.truth[1]:.2f}, {self.truth[2]:.2f})"
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        self.contacts.append(f"t={stamp:.1f} s contact ({msg.point.x:.2f}, {msg.point.y:.2f}) robot {robot}")

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        truth = self.truth_at(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9)
        if truth is not None:
            p = msg.pose.pose.position
            self.errors.append(math.hypot(p.x - truth[0], p.y - truth[1]))

    def close(self) -> None:
        self._spin.stop()  # first: nothing may be destroyed under a spinning thread
        self.lockstep.destroy()
        self.tf.destroy()
        self.node.destroy_node()


@pytest.mark.timeout(EXPLORE_WALL_S + 300)  # phase 2: a new stack and three goals, about 70 s
def test_explore_save_and_navigate_on_the_saved_map(ros_context: Any, tmp_path: Path) -> None:
    probe = Probe(ros_context)
    map_file = tmp_path / "explored"
    try:
        sim = sim_spec(SYSTEM_RTF, participants=SLAM_ROLES)
        stack = Stack([sim, *slam_processes(PARAMS_FILE), *nav_specs()])
        try:
            done = explore(map_file, max_time=EXPLORE_SIM_S, timeout=EXPLORE_WALL_S)
            print(done.stdout[-4000:], done.stderr[-4000:])  # goals and warnings, shown when the test fails
            assert done.returncode == 0, (f"robot at {probe.truth} (t, x, y)\n" + done.stdout[-3000:]
                                          + done.stderr[-3000:] + stack.tail())
            assert "exploration complete" in done.stdout
            numbers = progress_numbers(done.stdout)
            iou = compare_with_reference(map_file.with_suffix(".yaml"))
            errors = sorted(probe.errors)
            median = errors[len(errors) // 2]
            print(f"\nexploration: {numbers}, IoU {iou:.3f}, pose error median {median:.3f} "
                  f"max {errors[-1]:.3f} m over {len(errors)} poses")
            assert probe.collisions and probe.collisions[-1] == 0, f"collisions: {probe.contacts}"
            assert iou >= 0.8, f"occupied IoU with the reference {iou:.3f}"
            assert len(errors) > 50 and median <= SLAM_MAX_MEDIAN_ERROR and errors[-1] <= SLAM_MAX_ERROR, \
                f"SLAM pose error: median {median:.3f} m, max {errors[-1]:.3f} m"
        finally:
            stack.close()

        saved = load_map(map_file.with_suffix(".yaml"))
        assert (saved.data == -1).any(), "unknown cells must stay unknown after the round trip"
        sim = sim_spec(SYSTEM_RTF, participants=SAVED_MAP_ROLES)
        stack = Stack([sim, *saved_map_specs(map_file.with_suffix(".yaml"))])
        try:
            # The stack is active (its ready line), and AMCL publishes map -> odom only after its
            # first scan: wait for AMCL's pose, as BasicNavigator does.
            wait_until(lambda: bool(probe.amcl_poses) or not stack.alive(), 60.0, "/amcl_pose")
            wait_until(lambda: probe.navigate.server_is_ready() or not stack.alive(), 60.0,
                       "navigate_to_pose")
            # This process gets AMCL's map -> odom a while after /amcl_pose (the stack's controller
            # shares AMCL's process and has it at once). Phase 1's transforms would answer at once.
            probe.tf.buffer.clear()
            probe.tf.wait_for("map", "base_link", timeout=30.0)
            for target in GOALS:
                goal = NavigateToPose.Goal()
                goal.pose = pose_stamped(*target, "map", probe.node.get_clock().now().to_msg())
                sent = send_until_acknowledged(probe.navigate, goal, 30.0)
                assert sent.result().accepted
                result = sent.result().get_result_async()
                wait_until(lambda r=result: r.done() or not stack.alive(), 300.0, "the navigation result")
                assert result.done(), stack.tail()
                assert result.result().status == GoalStatus.STATUS_SUCCEEDED, \
                    (target, result.result().result.error_msg)
                assert probe.truth is not None
                assert math.hypot(probe.truth[1] - target[0], probe.truth[2] - target[1]) < 0.5, target
        finally:
            stack.close()
    finally:
        probe.close()
