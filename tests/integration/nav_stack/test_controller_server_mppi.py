"""controller_server with ``FollowPath.plugin: nav2_mppi_controller::MPPIController`` drives sim2d's
waffle along a planned path to SUCCEEDED, publishing the optimal trajectory on local_plan and, for a
subscriber, Jazzy's TrajectoryVisualizer topics.

The rig is test_controller_server.py's: sim2d in lockstep with this process (the servers spin in the
harness's executor with the ``controller_test`` participant), so the robot moves by sim time however
slowly this machine answers. MPPI's parameters are parameter overrides on top of nav2_params.yaml.
The samples' markers are thinned (trajectory_step 50): this process deserializes what it receives
in Python, 230 ms for Jazzy's 7656 markers, in the executor thread the servers share.
"""

from __future__ import annotations

import math
import subprocess
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped, Twist
from nav2_msgs.action import ComputePathToPose, FollowPath
from nav_msgs.msg import Path
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.serialization import deserialize_message, serialize_message
from visualization_msgs.msg import MarkerArray

from nav_stack.core.control.mppi import MPPIController, trajectory_markers
from nav_stack.ros.control import controller_server
from nav_stack.ros.control.mppi_visualization import SphereArrayEncoder, _sphere
from nav_stack.ros.planning import planner_server
from navsuite_testing.nav.world import (
    Harness,
    WorldNode,
    get_result,
    send_goal,
    server_args,
    start_sim,
    stop_process,
)
from navsuite_testing.ros import wait_until
from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.lockstep import LockstepParticipant

pytestmark = pytest.mark.ros
LOCKSTEP_ROLE = "controller_test"
MPPI = [  # Jazzy's TB3 MPPI, at the waffle's top speed, the samples' visualisation thinned further
    Parameter("FollowPath.plugin", value="nav2_mppi_controller::MPPIController"),
    Parameter("FollowPath.vx_max", value=0.26),
    Parameter("FollowPath.wz_max", value=1.0),
    Parameter("FollowPath.batch_size", value=1000),
    Parameter("FollowPath.TrajectoryVisualizer.trajectory_step", value=50),
    Parameter("FollowPath.CostCritic.cost_weight", value=3.81),
]


@pytest.fixture(scope="module")
def sim() -> Iterator[subprocess.Popen[str]]:
    proc = start_sim(rtf=2.0, lockstep=True)
    try:
        yield proc
    finally:
        stop_process(proc)


class Stack:
    """planner_server + controller_server (MPPI) with their costmaps, the world and a probe node."""

    def __init__(self, context: Any) -> None:
        self.harness = Harness(context)
        self.world = WorldNode(context=context)
        self.probe = Node("mppi_probe", context=context)
        self.planner_nodes = planner_server.build_nodes(use_sim_time=True, context=context,
                                                        cli_args=server_args())
        self.controller_nodes = controller_server.build_nodes(
            use_sim_time=True, context=context, cli_args=server_args(), parameter_overrides=MPPI)
        self.cmds: list[Twist] = []
        self.local_plans: list[Path] = []
        self.markers: list[MarkerArray] = []
        self.plans: list[Path] = []
        self.probe.create_subscription(Twist, "/cmd_vel", self.cmds.append, 100)
        self.probe.create_subscription(Path, "/local_plan", self.local_plans.append, 10)
        self.probe.create_subscription(MarkerArray, "/trajectories", self.markers.append, 10)
        self.probe.create_subscription(Path, "/transformed_global_plan", self.plans.append, 10)
        self.lockstep: LockstepParticipant | None = None
        self.harness.add(self.world, self.probe, *self.planner_nodes, *self.controller_nodes)
        self.planner = ActionClient(self.probe, ComputePathToPose, "compute_path_to_pose")
        self.follow = ActionClient(self.probe, FollowPath, "follow_path")

    def start(self) -> None:
        wait_until(lambda: self.world.truth is not None, 20.0, "sim2d ground truth")
        self.world.reset_sim()
        self.harness.bring_up(self.planner_nodes[0])
        self.harness.bring_up(self.controller_nodes[0])
        wait_until(self.planner_nodes[1].ready.done, 40.0, "global costmap never updated")
        wait_until(self.controller_nodes[1].ready.done, 40.0, "local costmap never updated")
        self.lockstep = LockstepParticipant(self.probe, LOCKSTEP_ROLE)

    def close(self) -> None:
        self.harness.stop()
        if self.lockstep is not None:
            self.lockstep.destroy()
        self.harness.close()

    def plan(self, x: float, y: float, yaw: float = 0.0) -> Path:
        goal = PoseStamped()
        goal.header.frame_id = "map"
        goal.pose.position.x, goal.pose.position.y = x, y
        goal.pose.orientation.z, goal.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        status, result = get_result(send_goal(self.planner, ComputePathToPose.Goal(goal=goal)), 20.0)
        assert status == GoalStatus.STATUS_SUCCEEDED, result.error_msg
        return result.path


@pytest.fixture
def stack(ros_context: Any, sim: subprocess.Popen[str]) -> Iterator[Stack]:
    s = Stack(ros_context)
    try:
        s.start()
        yield s
    finally:
        s.close()


def test_mppi_follows_a_planned_path_to_the_goal(stack: Stack) -> None:
    server = stack.controller_nodes[0]
    controller = server.plugins.controllers["FollowPath"]
    assert isinstance(controller, MPPIController)
    assert controller.params.vx_max == 0.26 and controller.params.batch_size == 1000
    assert controller.params.time_steps == 56 and controller.params.critics[1] == "CostCritic"
    handle = send_goal(stack.follow, FollowPath.Goal(path=stack.plan(2.0, 0.0), controller_id="FollowPath",
                                                     goal_checker_id="general_goal_checker"))
    status, result = get_result(handle, 150.0)
    assert status == GoalStatus.STATUS_SUCCEEDED, (result.error_code, result.error_msg, stack.world.pose())
    x, y, _ = stack.world.pose()
    assert math.hypot(x - 2.0, y) < 0.25 + 0.05
    assert stack.world.collisions == 0
    assert max(c.linear.x for c in stack.cmds) <= 0.26 + 1e-9
    assert any(c.linear.x > 0.2 for c in stack.cmds), "MPPI never drove near vx_max"
    wait_until(lambda: stack.cmds[-1].linear.x == 0.0 and stack.cmds[-1].angular.z == 0.0, 5.0,
               "a final zero command")
    assert stack.local_plans and len(stack.local_plans[-1].poses) == 56
    assert stack.local_plans[-1].header.frame_id == "odom"
    wait_until(lambda: bool(stack.markers) and bool(stack.plans), 10.0, "the TrajectoryVisualizer topics")
    markers = stack.markers[-1].markers
    candidates = [m for m in markers if m.ns == "Candidate Trajectories"]
    optimal = [m for m in markers if m.ns == "Optimal Trajectory"]
    assert len(candidates) == (1000 // 50) * math.ceil(56 / 3) and len(optimal) == 56
    assert [m.id for m in markers] == list(range(len(markers)))
    assert candidates[0].type == candidates[0].SPHERE and candidates[0].header.frame_id == "odom"
    assert stack.plans[-1].header.frame_id == "odom" and stack.plans[-1].poses


@pytest.mark.parametrize("frame, batch, steps, trajectory_step, time_step", [
    ("odom", 2000, 56, 5, 3), ("map", 7, 5, 2, 2), ("x", 1, 3, 1, 1)])
def test_the_sphere_encoder_serializes_what_rclpy_would(frame: str, batch: int, steps: int,
                                                         trajectory_step: int, time_step: int) -> None:
    """The markers MPPIVisualization publishes as bytes are the messages Marker objects would give."""
    rng = np.random.default_rng(batch)
    x, y = rng.normal(size=(batch, steps)), rng.normal(size=(batch, steps))
    optimal = rng.normal(size=(steps, 3))
    sets = trajectory_markers(x, y, optimal, trajectory_step, time_step)
    encoded = deserialize_message(SphereArrayEncoder(frame).encode(sets), MarkerArray)
    objects = MarkerArray(markers=[
        _sphere(frame, s.namespace, int(i), c, d, rgba)
        for s in sets for i, c, d, rgba in zip(s.ids, s.centres, s.sizes, s.colours, strict=True)])
    assert encoded == deserialize_message(serialize_message(objects), MarkerArray)
    assert len(encoded.markers) == sum(len(s.ids) for s in sets)
