"""smoother_server: the SmoothPath action (``smooth_path``) of Nav2 Jazzy's nav2_smoother.

Plugins: ``smoother_plugins`` lists ids, each typed by ``<id>.plugin`` (nav2_smoother::SimpleSmoother,
knobs under ``<id>.``); an unknown type fails configure naming the parameter, its value and the
supported types. A goal names its plugin by ``smoother_id`` (empty: the only plugin).

Inputs, as Nav2's server takes them: the costmap as nav2_msgs/Costmap on ``costmap_topic`` and the
robot outline as PolygonStamped on ``footprint_topic`` (both reliable, transient local: the costmap
node publishes them latched). The outline is brought into the robot frame through TF when a goal
needs it; until one arrives the robot is a 0.22 m circle, as behavior_server assumes.
``transform_tolerance`` is declared for Nav2 files; TF answers with the latest transforms.

Per goal (a coroutine): the smoother id and the path are checked (INVALID_SMOOTHER, INVALID_PATH for
an empty path, a non-finite pose or an empty frame_id), then the path is brought into the costmap's
frame (INVALID_PATH when TF cannot), smoothed on the node's worker thread (the executor goes on
serving; a cancel stops the smoothing within a sweep; in lockstep the simulator is held meanwhile, so
smoothing takes no sim time), brought back into its own frame, published on ``plan_smoothed`` and
returned. No costmap yet is UNKNOWN, as Nav2's server fails without one. ``smoothing_duration`` is the
compute time (wall s, what ``max_smoothing_duration`` bounds).
"""

from __future__ import annotations

import copy
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from geometry_msgs.msg import PolygonStamped
from nav2_msgs.action import SmoothPath
from nav2_msgs.msg import Costmap
from nav_msgs.msg import Path
from rclpy.action import GoalResponse
from rclpy.node import Node

from nav_stack.core.control import CircleFootprint, CostGrid, PolygonFootprint
from nav_stack.core.geometry import FloatArray, from_frame, to_frame
from nav_stack.core.smoothing import (
    SimpleSmoother,
    SimpleSmootherParams,
    SmoothErrorCode,
    SmootherServerCore,
    SmoothingError,
    SmoothResult,
    check_path,
)
from nav_stack.ros.bringup.param_layout import param
from nav_stack.ros.common.conversions import (
    duration_msg,
    duration_to_seconds,
    path_to_array,
    yaw_to_quaternion,
)
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.docking.docking_world import cost_grid
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.runtime.actions import RESULT_TIMEOUT_S, ActionServer
from ros_tools.runtime.coroutines import until
from ros_tools.runtime.lockstep import hold_process
from ros_tools.runtime.offload import CancelFlags, Offload

#: plugin type (last part of ``<id>.plugin``) -> (parameter dataclass, smoother class)
SMOOTHER_TYPES: dict[str, tuple[type, type]] = {"SimpleSmoother": (SimpleSmootherParams, SimpleSmoother)}
DEFAULT_PLUGIN = {"simple_smoother": "nav2_smoother::SimpleSmoother"}
#: wall s the simulator is held beyond a goal's max_smoothing_duration (the worker may be queued)
HOLD_MARGIN = 1.0


@dataclass(frozen=True)
class SmootherServerParams:
    """smoother_server knobs (Nav2 Jazzy defaults)."""

    smoother_plugins: tuple[str, ...] = ("simple_smoother",)
    costmap_topic: str = "global_costmap/costmap_raw"
    footprint_topic: str = "global_costmap/published_footprint"
    robot_base_frame: str = "base_link"
    transform_tolerance: float = 0.1  # s
    action_server_result_timeout: float = RESULT_TIMEOUT_S  # s a finished goal's result is kept


class SmootherServer(NavLifecycleNode):
    """The ``smoother_server`` node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("smoother_server", **kwargs)
        self._active = False
        self._grid: tuple[CostGrid, str] | None = None
        self._footprint_msg: PolygonStamped | None = None
        self._entities: list[Any] = []

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, SmootherServerParams)
        smoothers: dict[str, SimpleSmoother] = {}
        for smoother_id in p.smoother_plugins:
            plugin = str(param(self, f"{smoother_id}.plugin", DEFAULT_PLUGIN.get(smoother_id, "")))
            kind = plugin.replace("/", "::").split("::")[-1]
            if kind not in SMOOTHER_TYPES:
                raise ValueError(f"smoother_server: {smoother_id}.plugin '{plugin}' is not one of "
                                 f"{sorted(SMOOTHER_TYPES)}")
            params_cls, smoother_cls = SMOOTHER_TYPES[kind]
            smoothers[smoother_id] = smoother_cls(declare_dataclass(self, params_cls, f"{smoother_id}."))
        self.core = SmootherServerCore(smoothers)
        self.frames = Frames(self, p.robot_base_frame)
        self._offload = Offload(self, "smoother")
        self._cancels = CancelFlags()
        self._pub_plan = self.create_publisher(Path, "plan_smoothed", 1)
        self._entities = [
            self.create_subscription(Costmap, p.costmap_topic, self._on_costmap, LATCHED),
            self.create_subscription(PolygonStamped, p.footprint_topic, self._on_footprint, LATCHED),
        ]
        self._server = ActionServer(self, SmoothPath, "smooth_path", self._execute,
                                    goal_callback=self._accept_goal, cancel_callback=self._cancels.on_cancel,
                                    result_timeout=round(p.action_server_result_timeout))
        self.get_logger().info(f"smoothers: {', '.join(smoothers)}")

    def activate(self) -> None:
        self._active = True

    def deactivate(self) -> None:
        self._active = False

    def cleanup(self) -> None:
        self._server.destroy()
        self._cancels.set_all()  # a smoothing still running stops at its next sweep
        self._offload.destroy()
        for sub in self._entities:
            self.destroy_subscription(sub)
        self._entities = []
        self.destroy_publisher(self._pub_plan)
        self.frames.destroy()
        self._grid, self._footprint_msg = None, None

    # -- inputs ------------------------------------------------------------------------------------
    def _on_costmap(self, msg: Costmap) -> None:
        self._grid = (cost_grid(msg), msg.header.frame_id.lstrip("/"))

    def _on_footprint(self, msg: PolygonStamped) -> None:
        self._footprint_msg = msg

    def _footprint(self) -> Any:
        """The robot outline in the robot frame, from the last published footprint (Nav2's way)."""
        msg = self._footprint_msg
        if msg is None or len(msg.polygon.points) < 3:
            return CircleFootprint()
        try:
            robot = self.frames.robot_pose(msg.header.frame_id.lstrip("/"))
        except FrameError:
            return CircleFootprint()
        local = to_frame(np.array([(q.x, q.y, 0.0) for q in msg.polygon.points]), robot)
        return PolygonFootprint(tuple((float(x), float(y)) for x, y in local[:, :2]))

    # -- goals -------------------------------------------------------------------------------------
    def _accept_goal(self, goal: Any) -> GoalResponse:
        return GoalResponse.ACCEPT if self._active else GoalResponse.REJECT

    async def _execute(self, handle: Any) -> SmoothPath.Result:
        goal = handle.request
        self.get_logger().info(f"received a path of {len(goal.path.poses)} poses to smooth")
        with self._cancels.held(handle) as cancelled:
            result, frame_pose = await self._smooth(goal, cancelled)
        return self._finish(handle, result, frame_pose)

    async def _smooth(self, goal: Any, cancelled: threading.Event) -> tuple[SmoothResult, Any]:
        """The core's result, and the pose of the path's frame in the costmap's (None: the same)."""
        poses = path_poses(goal.path)
        try:
            self.core.smoother(goal.smoother_id)
            check_path(poses)
            frame = goal.path.header.frame_id.lstrip("/")
            if not frame:
                raise SmoothingError(SmoothErrorCode.INVALID_PATH, "the path has an empty header.frame_id")
            if self._grid is None:
                raise SmoothingError(SmoothErrorCode.UNKNOWN,
                                     f"no costmap received on '{self.params.costmap_topic}' yet")
            grid, grid_frame = self._grid
            frame_pose = None if frame == grid_frame else self._frame_pose(grid_frame, frame)
        except SmoothingError as error:
            return SmoothResult(error_code=error.code, error_msg=error.message), None
        in_grid = poses if frame_pose is None else from_frame(poses, frame_pose)
        footprint = self._footprint() if goal.check_for_collisions else None
        max_duration = duration_to_seconds(goal.max_smoothing_duration)
        answer = self._offload.submit(self.core.smooth_path, in_grid, goal.smoother_id, max_duration, grid,
                                      goal.check_for_collisions, footprint, cancelled.is_set)
        hold_process(answer.done, max(max_duration, 0.0) + HOLD_MARGIN, wake=answer)
        try:
            result: SmoothResult = await until(answer)
        except Exception as error:  # a smoother bug, or a cleanup meanwhile: a result, not a crash
            message = f"{type(error).__name__}: {error}"
            self.get_logger().error(f"smoothing failed: {message}")
            return SmoothResult(error_code=SmoothErrorCode.UNKNOWN, error_msg=message), None
        return result, frame_pose

    def _frame_pose(self, grid_frame: str, frame: str) -> Any:
        try:
            return self.frames.frame_pose(grid_frame, frame)
        except FrameError as error:
            raise SmoothingError(SmoothErrorCode.INVALID_PATH,
                                 f"the path's frame cannot be brought into the costmap's: {error}") from error

    def _finish(self, handle: Any, result: SmoothResult, frame_pose: Any) -> SmoothPath.Result:
        msg = SmoothPath.Result()
        msg.smoothing_duration = duration_msg(result.smoothing_duration)
        msg.was_completed = result.was_completed
        msg.error_code, msg.error_msg = int(result.error_code), result.error_msg
        if len(result.path):
            poses = result.path if frame_pose is None else to_frame(result.path, frame_pose)
            msg.path = with_poses(handle.request.path, poses)
            if result.was_completed:
                self._pub_plan.publish(msg.path)
        if handle.is_cancel_requested:
            handle.canceled()
        elif result.ok:
            handle.succeed()
        else:
            self.get_logger().warn(f"smooth_path failed ({result.error_code}): {result.error_msg}")
            handle.abort()
        return msg


def path_poses(path: Path) -> FloatArray:
    """(N, 3) x, y, yaw of a nav_msgs/Path; NaN yaw where the quaternion cannot be normalised (the
    core refuses it as INVALID_PATH)."""
    return path_to_array(path, invalid_yaw=math.nan)


def with_poses(path: Path, poses: FloatArray) -> Path:
    """A copy of ``path`` with the positions and headings of ``poses`` (N, 3): headers and z are kept,
    as Nav2's smoother edits the goal's path in place."""
    out = copy.deepcopy(path)
    for stamped, (x, y, yaw) in zip(out.poses, poses, strict=True):
        stamped.pose.position.x, stamped.pose.position.y = float(x), float(y)
        stamped.pose.orientation = yaw_to_quaternion(float(yaw))
    return out


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The smoother_server node (a list, like the other servers' ``build_nodes``)."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [SmootherServer(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.planning.smoother_server [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role="smoother_server")


if __name__ == "__main__":
    raise SystemExit(main())
