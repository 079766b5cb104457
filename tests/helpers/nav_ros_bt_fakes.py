"""Scripted Nav2 servers for bt_navigator / waypoint_follower tests (one rclpy node, no real stack).

``FakeNav2`` serves compute_path_to_pose, compute_path_through_poses, follow_path, spin, backup,
drive_on_heading, wait, the two clear_entirely_* services, and publishes a static map → base_link
transform (the robot sits at ``robot_xy``). Every goal, cancel and call is recorded. Behaviour
is scripted through attributes:

* ``occupied``: goal positions (rounded to 0.01 m) the planner refuses with GOAL_OCCUPIED (206);
* ``follow_codes``: error codes FollowPath aborts with, one per goal (0 or an empty list = succeed);
* ``follow_steps``: how many 10 ms polls a FollowPath goal runs before it ends (wall clock);
* ``hold_follow``: while True, FollowPath goals keep running until canceled or preempted.
"""

from __future__ import annotations

import threading
from typing import Any

from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import (
    BackUp,
    ComputePathThroughPoses,
    ComputePathToPose,
    DriveOnHeading,
    FollowPath,
    NavigateToPose,
    Spin,
    Wait,
)
from nav2_msgs.srv import ClearEntireCostmap
from nav_msgs.msg import Path
from rclpy.action import CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.node import Node

from ros_tools.runtime.actions import ActionServer
from ros_tools.runtime.waiting import sleep, steady_clock
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg
from ros_tools.tf.transform import Transform

POLL = 0.01  # s


def straight_path(x0: float, y0: float, x1: float, y1: float, frame: str = "map", n: int = 20) -> Path:
    path = Path()
    path.header.frame_id = frame
    for i in range(n + 1):
        pose = PoseStamped()
        pose.header.frame_id = frame
        pose.pose.position.x = x0 + (x1 - x0) * i / n
        pose.pose.position.y = y0 + (y1 - y0) * i / n
        pose.pose.orientation.w = 1.0
        path.poses.append(pose)
    return path


class FakeNav2(Node):
    """Scripted planner, controller and behaviour servers plus a static robot pose in TF."""

    def __init__(self, robot_xy: tuple[float, float] | None = (0.0, 0.0), **kwargs: Any) -> None:
        """``robot_xy``: where map -> base_link puts the robot (m); None: no robot pose at all."""
        super().__init__("fake_nav2", **kwargs)
        self.robot_xy = robot_xy
        self.occupied: set[tuple[float, float]] = set()
        self.follow_codes: list[int] = []
        self.follow_steps = 30
        self.hold_follow = False
        self.rejecting: set[str] = set()  # action names whose goals are rejected
        self._follow_generation = 0
        self.goals: dict[str, list[Any]] = {}
        self.cancels: dict[str, int] = {}
        self.calls: dict[str, int] = {}
        self._lock = threading.Lock()
        group = ReentrantCallbackGroup()
        self._servers = [
            self._server(ComputePathToPose, "compute_path_to_pose", self._plan, group),
            self._server(ComputePathThroughPoses, "compute_path_through_poses", self._plan_through, group),
            self._server(FollowPath, "follow_path", self._follow, group),
            self._server(Spin, "spin", self._instant, group),
            self._server(BackUp, "backup", self._instant, group),
            self._server(DriveOnHeading, "drive_on_heading", self._instant, group),
            self._server(Wait, "wait", self._instant, group),
        ]
        for costmap in ("global_costmap", "local_costmap"):
            name = f"{costmap}/clear_entirely_{costmap}"
            self.create_service(ClearEntireCostmap, name, self._clear_handler(name), callback_group=group)
        self._static = StaticTransformBroadcaster(self)
        if robot_xy is not None:
            x, y = robot_xy
            self._static.send([transform_to_msg(Transform(x, y, 0.0, 0.0, 0.0, 0.0, 1.0), "map",
                                                "base_link", self.get_clock().now().to_msg())])

    # -- bookkeeping ------------------------------------------------------------------------------
    def _server(self, action_type: Any, name: str, execute: Any, group: Any) -> ActionServer:
        def on_goal(goal: Any) -> GoalResponse:
            with self._lock:
                self.goals.setdefault(name, []).append(goal)
            return GoalResponse.REJECT if name in self.rejecting else GoalResponse.ACCEPT

        def on_cancel(_handle: Any) -> CancelResponse:
            with self._lock:
                self.cancels[name] = self.cancels.get(name, 0) + 1
            return CancelResponse.ACCEPT

        return ActionServer(self, action_type, name, execute, callback_group=group, goal_callback=on_goal,
                            cancel_callback=on_cancel)

    def _clear_handler(self, name: str) -> Any:
        def handle(request: Any, response: Any) -> Any:
            with self._lock:
                self.calls[name] = self.calls.get(name, 0) + 1
            return response
        return handle

    def count(self, name: str) -> int:
        with self._lock:
            return len(self.goals.get(name, []))

    # -- servers ------------------------------------------------------------------------------------
    def _plan(self, handle: Any) -> Any:
        goal = handle.request.goal
        result = ComputePathToPose.Result()
        key = (round(goal.pose.position.x, 2), round(goal.pose.position.y, 2))
        if key in self.occupied:
            result.error_code = ComputePathToPose.Result.GOAL_OCCUPIED
            result.error_msg = f"goal {key} is in an occupied cell"
            handle.abort()
            return result
        result.path = straight_path(*self.robot_xy, goal.pose.position.x, goal.pose.position.y)
        result.path.header.stamp = self.get_clock().now().to_msg()  # each plan differs, as a real one does
        handle.succeed()
        return result

    def _plan_through(self, handle: Any) -> Any:
        result = ComputePathThroughPoses.Result()
        last = handle.request.goals[-1].pose.position
        result.path = straight_path(*self.robot_xy, last.x, last.y)
        handle.succeed()
        return result

    async def _follow(self, handle: Any) -> Any:
        result = FollowPath.Result()
        with self._lock:
            code = self.follow_codes.pop(0) if self.follow_codes else 0
            self._follow_generation += 1
            generation = self._follow_generation
        steps = 0
        while self.hold_follow or steps < self.follow_steps:
            if handle.is_cancel_requested:
                handle.canceled()
                return result
            if generation != self._follow_generation:  # preempted by a newer goal, as controller_server does
                handle.abort()
                return result
            await sleep(self, POLL, steady_clock())  # never blocks: the executor has one thread
            steps += 1
        if code:
            result.error_code = code
            result.error_msg = f"scripted controller failure {code}"
            handle.abort()
        else:
            handle.succeed()
        return result

    def _instant(self, handle: Any) -> Any:
        handle.succeed()
        return _result_for(handle)


def _result_for(handle: Any) -> Any:
    goal_type = type(handle.request)
    for action in (Spin, BackUp, DriveOnHeading, Wait):
        if goal_type is action.Goal:
            return action.Result()
    raise TypeError(goal_type)


def nav_goal(x: float, y: float, frame: str = "map", behavior_tree: str = "") -> NavigateToPose.Goal:
    goal = NavigateToPose.Goal()
    goal.pose.header.frame_id = frame
    goal.pose.pose.position.x = x
    goal.pose.pose.position.y = y
    goal.pose.pose.orientation.w = 1.0
    goal.behavior_tree = behavior_tree
    return goal


class FakeNavigateToPose(Node):
    """A navigate_to_pose server: goals at ``failing`` positions abort with ``fail_code``; others
    succeed after ``steps`` 10 ms polls; ``hold`` keeps goals running until canceled."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("fake_navigator", **kwargs)
        self.failing: set[tuple[float, float]] = set()
        self.fail_code = 208
        self.steps = 5
        self.hold = False
        self.goals: list[Any] = []
        self.canceled = 0
        self._server = ActionServer(self, NavigateToPose, "navigate_to_pose", self._execute,
                                    callback_group=ReentrantCallbackGroup(),
                                    cancel_callback=lambda _h: CancelResponse.ACCEPT)

    async def _execute(self, handle: Any) -> Any:
        position = handle.request.pose.pose.position
        self.goals.append((position.x, position.y))
        result = NavigateToPose.Result()
        steps = 0
        while self.hold or steps < self.steps:
            if handle.is_cancel_requested:
                self.canceled += 1
                handle.canceled()
                return result
            await sleep(self, POLL, steady_clock())  # never blocks: the executor has one thread
            steps += 1
        if (position.x, position.y) in self.failing:
            result.error_code = self.fail_code
            result.error_msg = "scripted failure"
            handle.abort()
        else:
            handle.succeed()
        return result
