"""SLAM system run (seed 001): explore turtlebot3_world without a human, save the map, navigate on it.

Phase 1: sim2d (default drifting odometry) + the SLAM processes of ``nav-bringup --slam``
(nav_stack.ros.slam.slam_bringup) + the Nav2 servers; ``nav-explore -f <map>`` drives NavigateToPose goals
from the seeds' spawn (-2.0, -0.5, 0) until no reachable frontier is left, then saves the map.

Map check: the reference maps/turtlebot3_world.yaml also marks the solid blocks' interiors and
cells outside the wall, which no lidar inside the arena can see. So the truth is restricted to the
*observable* occupied cells: those 8-adjacent to the reference's free space connected to the spawn
(navsuite_testing.slam.stack.observable_walls). The SLAM map's occupied cells are compared
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

import math
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("nav_stack.ros.planning.planner_server", reason="the Nav2 servers do not exist yet")
pytest.importorskip("nav_stack.ros.navigator.bt_navigator", reason="the Nav2 servers do not exist yet")
pytest.importorskip("nav_stack.ros.slam.map_saver", reason="map_saver does not exist yet")

from action_msgs.msg import GoalStatus
from nav2_msgs.action import NavigateToPose

from nav_stack.core.map_io import load_map
from nav_stack.ros.common.conversions import pose_stamped
from nav_stack.ros.slam.slam_bringup import slam_processes
from navsuite_testing.ros import SYSTEM_RTF, wait_until
from navsuite_testing.slam.stack import (
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
from navsuite_testing.slam.system_probe import PROBE_ROLE, Probe
from ros_tools.runtime.actions import send_until_acknowledged
from tests.helpers.nav_ros_slam_drive import SLAM_MAX_ERROR, SLAM_MAX_MEDIAN_ERROR

pytestmark = [pytest.mark.slow, pytest.mark.ros]
#: The processes the simulator waits for in lockstep (their run_nodes roles, and this test's probe).
SLAM_ROLES = ("slam", *NAV_SERVERS, PROBE_ROLE)
SAVED_MAP_ROLES = ("nav2", PROBE_ROLE)  # phase 2: the one-process stack, as nav-bringup runs it
#: Phase 2's goals (x, y, yaw; map frame): spawns of sim2d/worlds/turtlebot3_world.yaml, so free.
GOALS = ((0.0, 2.0, 0.0), (1.9, 0.0, math.pi), (-2.0, -0.5, 0.0))
#: Exploring takes 90-150 sim s here; the limits end a stuck run with the explorer's log.
EXPLORE_SIM_S, EXPLORE_WALL_S = 300.0, 360.0


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
