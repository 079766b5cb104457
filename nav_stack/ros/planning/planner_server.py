"""planner_server: ComputePathToPose / ComputePathThroughPoses on the global costmap (Nav2 names).

The node owns the ``global_costmap`` CostmapROS node (same process, driven through its lifecycle
from ours, as Nav2's planner_server does) and a core :class:`PlannerServerCore` holding the plugins
listed in ``planner_plugins`` (``<id>.plugin``: nav2_navfn_planner::NavfnPlanner or
nav2_theta_star_planner::ThetaStarPlanner, knobs under ``<id>.``). A goal names its plugin by
``planner_id``; an empty id takes the last ``planner_selector`` message, else the first plugin.

Per goal (a coroutine: it awaits the costmap's first update on the node clock): poses are brought
into the costmap frame through TF (TF_ERROR when that fails, including an empty frame_id), the start
is the robot pose from TF unless ``use_start``, and the core returns the path or a Jazzy error code
with ``error_msg``. The search runs on the node's one worker thread (ros_tools.runtime.offload), so
plans are serialised in the order the goals arrived, and the executor thread goes on serving the
controller and the cancel requests meanwhile: a cancel stops the search within 2048 expansions
(Nav2 Jazzy's ``cancel_checker``) and the goal ends CANCELED. In lockstep the simulator is held
until the plan is back (at most PLAN_HOLD wall s), so a plan takes no sim time, as before, however
slow the machine. A NaN or zero-norm orientation is refused with
UNKNOWN and a message. Successful paths are published on ``plan``. ``is_path_valid`` reports path
poses on inscribed/lethal cells or off the map.

A path of a warehouse plan has about a thousand poses (3 cm cells): the result is built by
conversions.path_from_array, which fills the messages' slots instead of running their constructors.
``plan`` is published only while someone subscribes (it is volatile: nobody could read it later).
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from nav2_msgs.action import ComputePathThroughPoses, ComputePathToPose
from nav2_msgs.srv import IsPathValid
from nav_msgs.msg import Path
from rclpy.action import GoalResponse
from rclpy.node import Node
from rclpy.qos import QoSProfile

from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE
from nav_stack.core.planning import (
    NavfnParams,
    NavfnPlanner,
    PlanErrorCode,
    PlannerServerCore,
    PlanResult,
    ThetaStarParams,
    ThetaStarPlanner,
    ThroughPosesErrorCode,
)
from nav_stack.core.planning.common import GlobalPlanner
from nav_stack.ros.bringup.param_layout import param
from nav_stack.ros.common.conversions import duration_msg, path_from_array
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass, on_dataclass_update
from nav_stack.ros.common.selectors import Selector
from nav_stack.ros.costmap.costmap_ros import CostmapROS, run_transition
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.runtime.actions import RESULT_TIMEOUT_S, ActionServer
from ros_tools.runtime.coroutines import until
from ros_tools.runtime.lockstep import hold_process
from ros_tools.runtime.offload import CancelFlags, Offload
from ros_tools.runtime.waiting import wait_for

#: plugin type (last part of ``<id>.plugin``) -> (parameter dataclass, planner class)
PLANNER_TYPES: dict[str, tuple[type, type]] = {
    "NavfnPlanner": (NavfnParams, NavfnPlanner),
    "ThetaStarPlanner": (ThetaStarParams, ThetaStarPlanner),
}
DEFAULT_PLUGIN = {"GridBased": "nav2_navfn_planner::NavfnPlanner",
                  "ThetaStar": "nav2_theta_star_planner::ThetaStarPlanner"}
#: wall s the simulator is held for one plan in lockstep (above max_planning_time's 2 s default,
#: under lockstep.timeout's 10 s)
PLAN_HOLD = 5.0


@dataclass(frozen=True)
class PlannerServerParams:
    """planner_server knobs (Nav2 code defaults; the Jazzy yaml sets expected_planner_frequency 20)."""

    expected_planner_frequency: float = 1.0  # Hz; a slower plan is logged as a warning
    planner_plugins: tuple[str, ...] = ("GridBased",)
    costmap_update_timeout: float = 1.0  # s a goal waits for a first costmap before TIMEOUT
    action_server_result_timeout: float = RESULT_TIMEOUT_S  # s a finished goal's result is kept


class PlannerServer(NavLifecycleNode):
    """The ``planner_server`` node; :attr:`costmap_node` must be spun by the same executor."""

    def __init__(self, costmap_node: CostmapROS | None = None, **kwargs: Any) -> None:
        super().__init__("planner_server", **kwargs)
        self.costmap_node = costmap_node or CostmapROS("global_costmap", **kwargs)
        self._active = False
        self.core: PlannerServerCore | None = None
        self._entities: list[Any] = []
        self._param_callbacks: list[Any] = []
        self._offload: Offload | None = None
        self._cancels = CancelFlags()  # what a search polls to stop when its goal is cancelled

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        self.params = declare_dataclass(self, PlannerServerParams)
        planners: dict[str, GlobalPlanner] = {}
        updates: list[tuple[str, type, Any]] = []
        for planner_id in self.params.planner_plugins:
            plugin = str(param(self, f"{planner_id}.plugin", DEFAULT_PLUGIN.get(planner_id, "")))
            kind = plugin.replace("/", "::").split("::")[-1]
            if kind not in PLANNER_TYPES:
                raise ValueError(f"planner_server: {planner_id}.plugin '{plugin}' is not one of "
                                 f"{sorted(PLANNER_TYPES)}")
            params_cls, planner_cls = PLANNER_TYPES[kind]
            values: Any = declare_dataclass(self, params_cls, f"{planner_id}.")
            planners[planner_id] = planner_cls(values)
            updates.append((planner_id, planner_cls, values))
        self.core = PlannerServerCore(planners)
        self._param_callbacks = [self._take_param_updates(*update) for update in updates]
        run_transition(self.costmap_node, "configure")
        self._pub_plan = self.create_publisher(Path, "plan", QoSProfile(depth=1))
        self._offload = Offload(self, "planner")
        self._selector = Selector(self, "planner_selector")
        self._entities = [
            self._action(ComputePathToPose, "compute_path_to_pose", self._to_pose),
            self._action(ComputePathThroughPoses, "compute_path_through_poses", self._through_poses),
            self.create_service(IsPathValid, "is_path_valid", self._is_path_valid),
        ]

    def _action(self, action_type: Any, name: str, execute: Any) -> ActionServer:
        return ActionServer(self, action_type, name, execute, goal_callback=self._accept_goal,
                            cancel_callback=self._cancels.on_cancel,
                            result_timeout=round(self.params.action_server_result_timeout))

    def activate(self) -> None:
        run_transition(self.costmap_node, "activate")
        self._active = True

    def deactivate(self) -> None:
        self._active = False
        run_transition(self.costmap_node, "deactivate")

    def _take_param_updates(self, planner_id: str, planner_cls: type, values: Any) -> Any:
        """``ros2 param set /planner_server GridBased.tolerance 0.0`` rebuilds that planner with the new
        values (Nav2's planners take tolerance, use_astar, allow_unknown, ... at run time too)."""
        core = self.core
        assert core is not None
        latest = {"params": values}

        def rebuild(params: Any) -> None:
            latest["params"] = params
            core.planners[planner_id] = planner_cls(params)
            self.get_logger().info(f"{planner_id}: parameters updated")

        return on_dataclass_update(self, type(values), f"{planner_id}.", lambda: latest["params"], rebuild)

    def cleanup(self) -> None:
        for callback in self._param_callbacks:
            self.remove_on_set_parameters_callback(callback)
        self._param_callbacks = []
        for entity in self._entities:
            entity.destroy() if isinstance(entity, ActionServer) else self.destroy_service(entity)
        self._entities = []
        self._cancels.set_all()  # a search still running stops at its next poll
        if self._offload is not None:
            self._offload.destroy()
            self._offload = None
        self._selector.destroy()
        self.destroy_publisher(self._pub_plan)
        run_transition(self.costmap_node, "cleanup")

    def _accept_goal(self, goal: Any) -> GoalResponse:
        return GoalResponse.ACCEPT if self._active else GoalResponse.REJECT

    # -- planning ----------------------------------------------------------------------------------
    async def _plan(self, start_msg: Any, use_start: bool, goal_msgs: Sequence[Any], planner_id: str,
              through: bool, cancelled: threading.Event) -> PlanResult:
        codes: Any = ThroughPosesErrorCode if through else PlanErrorCode
        assert self.core is not None
        planner_id = self._selector.resolve(planner_id, self.params.planner_plugins[0])
        if planner_id not in self.core.planners:
            known = sorted(self.core.planners)
            return PlanResult(error_code=int(codes.INVALID_PLANNER),
                              error_msg=f"planner id '{planner_id}' is not one of {known}")
        if not await wait_for(self, self.costmap_node.ready, self.params.costmap_update_timeout):
            return PlanResult(error_code=int(codes.TIMEOUT), error_msg="the global costmap has no data yet "
                              f"(no map or no robot pose within {self.params.costmap_update_timeout} s)")
        snap = self.costmap_node.snapshot()
        assert snap is not None
        frames, frame = self.costmap_node.frames, self.costmap_node.global_frame
        assert frames is not None
        try:
            start = frames.to_frame(start_msg, frame) if use_start else frames.robot_pose(frame)
            goals = [frames.to_frame(g, frame) for g in goal_msgs]
        except FrameError as error:
            return PlanResult(error_code=int(codes.TF_ERROR), error_msg=str(error))
        assert self._offload is not None
        if through:
            answer = self._offload.submit(self.core.compute_path_through_poses, start, goals, planner_id,
                                          *snap, cancelled.is_set)
        else:
            answer = self._offload.submit(self.core.compute_path_to_pose, start, goals[0], planner_id,
                                          *snap, cancelled.is_set)
        hold_process(answer.done, PLAN_HOLD, wake=answer)
        result: PlanResult = await until(answer)
        limit = 1.0 / self.params.expected_planner_frequency
        if result.planning_time > limit:
            self.get_logger().warn(f"planning took {result.planning_time:.3f} s, more than the "
                                   f"{limit:.3f} s of expected_planner_frequency")
        return result

    def _finish(self, handle: Any, result_msg: Any, result: PlanResult) -> Any:
        stamp = self.get_clock().now().to_msg()
        result_msg.planning_time = duration_msg(result.planning_time)
        result_msg.error_code, result_msg.error_msg = result.error_code, result.error_msg
        if result.ok:
            result_msg.path = path_from_array(result.path, self.costmap_node.global_frame, stamp)
            if self._pub_plan.get_subscription_count() > 0:
                self._pub_plan.publish(result_msg.path)
        if handle.is_cancel_requested:
            handle.canceled()
        elif result.ok:
            handle.succeed()
        else:
            self.get_logger().warn(f"{handle.request.__class__.__name__} failed ({result.error_code}): "
                                   f"{result.error_msg}")
            handle.abort()
        return result_msg

    async def _to_pose(self, handle: Any) -> ComputePathToPose.Result:
        goal = handle.request
        with self._cancels.held(handle) as cancelled:
            result = await self._plan(goal.start, goal.use_start, [goal.goal], goal.planner_id, False,
                                      cancelled)
        return self._finish(handle, ComputePathToPose.Result(), result)

    async def _through_poses(self, handle: Any) -> ComputePathThroughPoses.Result:
        goal = handle.request
        with self._cancels.held(handle) as cancelled:
            result = await self._plan(goal.start, goal.use_start, list(goal.goals), goal.planner_id, True,
                                      cancelled)
        return self._finish(handle, ComputePathThroughPoses.Result(), result)

    def _is_path_valid(self, request: IsPathValid.Request, response: IsPathValid.Response
                       ) -> IsPathValid.Response:
        snap, frames = self.costmap_node.snapshot(), self.costmap_node.frames
        if snap is None or frames is None or not request.path.poses:
            response.is_valid = False
            return response
        costs, spec = snap
        try:
            poses = [frames.to_frame(p, self.costmap_node.global_frame) if p.header.frame_id
                     else frames.to_frame(_with_frame(p, request.path.header.frame_id),
                                          self.costmap_node.global_frame)
                     for p in request.path.poses]
        except FrameError as error:
            self.get_logger().warn(f"is_path_valid: {error}")
            response.is_valid = False
            return response
        xy = np.array([(p.x, p.y) for p in poses])
        mx, my = spec.world_to_cell(xy[:, 0], xy[:, 1])
        inside = spec.in_bounds(mx, my)
        cost = np.full(len(xy), 255)
        cost[inside] = costs[my[inside], mx[inside]]
        bad = ~inside | ((cost >= INSCRIBED_INFLATED_OBSTACLE) & (cost != 255))
        response.invalid_pose_indices = [int(i) for i in np.nonzero(bad)[0]]
        response.is_valid = not response.invalid_pose_indices
        return response


def _with_frame(pose: Any, frame: str) -> Any:
    pose.header.frame_id = frame
    return pose


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """planner_server and its global_costmap node, ready to add to one executor.

    ``kwargs`` go to both node constructors (``context``, ``cli_args`` with ``--params-file``, ...).
    """
    kwargs = with_sim_time(kwargs, use_sim_time)
    server = PlannerServer(**kwargs)
    return [server, server.costmap_node]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.planning.planner_server [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role="planner_server")


if __name__ == "__main__":
    raise SystemExit(main())
