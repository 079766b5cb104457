"""controller_server: FollowPath on the local costmap at ``controller_frequency`` (Nav2 Jazzy names, codes).

The node owns the ``local_costmap`` CostmapROS node (same process). Plugins are selected per goal by
``controller_id`` / ``goal_checker_id`` / ``progress_checker_id``; an empty id takes the last
``controller_selector`` / ``goal_checker_selector`` message, else the first configured plugin.

Each control cycle (a timer on the node clock, so sim time paces it): robot pose from TF in the
path's frame and in the costmap frame, speed from ``odom``; goal reached → zero command, SUCCEEDED;
progress checker → FAILED_TO_MAKE_PROGRESS (105), saying so when the robot did not move at all; a
robot that ignores its commands for ``response_timeout`` s because its battery is empty or its
odometry stopped → CONTROLLER_TIMED_OUT (107) naming the cause (no recovery can move it); else
the controller computes a command from the pruned local path. A controller that finds no valid
command publishes zero and, after ``failure_tolerance`` s, ends with PATIENCE_EXCEEDED (104), or at
once with NO_VALID_CONTROL (106) when the tolerance is 0 (Nav2's rule). An empty path is
INVALID_PATH (103), an unknown id INVALID_CONTROLLER (101), a missing transform TF_ERROR (102).

A new goal while one runs takes over at the next cycle: with the same controller the plugins keep
their state and only the path changes (no stop, the goal checker restarts); when the new path is
only the rest of the current one toward the same goal (the bt_navigator's 1 Hz replan, within
``path_reuse_tolerance``) the goal checker keeps its state too (follow_path.PathFollowing.take_over).
Either way the old goal is aborted with error code 0 and "preempted", as Nav2's action server does.
A cancel publishes a zero command inside the cancel callback, so the next /cmd_vel is zero.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from nav2_msgs.action import FollowPath
from nav_msgs.msg import Odometry, Path
from rclpy.action import CancelResponse, GoalResponse
from rclpy.node import Node

from nav_stack.core.control import (
    CircleFootprint,
    ControllerError,
    ControllerErrorCode,
    ControllerPlugins,
    CostGrid,
    InvalidController,
    PolygonFootprint,
    Twist2D,
)
from nav_stack.core.control.follow_path import (
    Action,
    CycleInputs,
    Decision,
    PathFollowing,
    Plugins,
    Takeover,
)
from nav_stack.core.costmap import CostmapParams
from nav_stack.ros.common.conversions import path_from_array, path_to_array
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.common.goal_runs import GoalRun, Outcome, cancel_current
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import DEFAULT
from nav_stack.ros.common.selectors import Selector
from nav_stack.ros.control.controller_plugins import build_plugins, take_param_updates
from nav_stack.ros.control.mppi_visualization import MPPIVisualization
from nav_stack.ros.control.response_monitor import ResponseMonitor
from nav_stack.ros.costmap.costmap_params import parse_footprint
from nav_stack.ros.costmap.costmap_ros import CostmapROS, run_transition
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.cmd_vel import CmdVelPublisher
from ros_tools.runtime.actions import RESULT_TIMEOUT_S, ActionServer
from ros_tools.runtime.timers import create_periodic_timer, nominal_call_ns

Code = ControllerErrorCode
_TAKEOVER_NOTES = {Takeover.FRESH: "", Takeover.NEW_PATH: " (path updated)",
                   Takeover.REMAINDER: " (the rest of the current path: only the path changed)"}


@dataclass(frozen=True)
class ControllerServerParams:
    """controller_server knobs (Nav2 code defaults; the Jazzy yaml sets failure_tolerance 0.3)."""

    controller_frequency: float = 20.0  # Hz
    controller_plugins: tuple[str, ...] = ("FollowPath",)
    goal_checker_plugins: tuple[str, ...] = ("general_goal_checker",)
    progress_checker_plugins: tuple[str, ...] = ("progress_checker",)
    failure_tolerance: float = 0.0  # s without a valid command before giving up; -1 = forever
    min_x_velocity_threshold: float = 0.0001  # m/s; odometry below it reads as 0
    min_theta_velocity_threshold: float = 0.0001  # rad/s
    costmap_update_timeout: float = 0.30  # s a goal waits for a first local costmap
    action_server_result_timeout: float = RESULT_TIMEOUT_S  # s a finished goal's result is kept
    enable_stamped_cmd_vel: bool = False
    odom_topic: str = "odom"
    # Not in Nav2: the robot's outline "[[x, y], ...]" (m, robot frame) that RPP and the rotation
    # shim also keep off lethal cells when the costmap models the robot as a robot_radius circle
    # that does not contain it (CircleFootprint.body); "[]" = the circle only.
    collision_footprint: str = "[]"
    # Not in Nav2: a robot still for response_timeout s (sim) under significant commands is checked
    # for a cause no recovery can fix (empty battery on battery_topic, odometry stopped) and the goal
    # ends with CONTROLLER_TIMED_OUT naming it (nav_stack/core/control/response.py). 0 / "" = off.
    response_timeout: float = 2.0
    battery_topic: str = "battery_state"
    # Not in Nav2 (whose C++ controllers make a new path cheap): a preempting goal whose path is the
    # rest of the current one toward the same goal, within this many m (follow_path.is_remainder),
    # keeps every plugin's state, the goal checker's latch included; 0 = never.
    path_reuse_tolerance: float = 0.1

    def __post_init__(self) -> None:
        if not self.controller_frequency > 0.0:
            raise ValueError(f"controller_frequency must be > 0 Hz, got {self.controller_frequency}")
        if not self.path_reuse_tolerance >= 0.0:
            raise ValueError(f"path_reuse_tolerance must be >= 0 m, got {self.path_reuse_tolerance}")


class _PathRun(GoalRun):
    """A FollowPath goal: its action handle and result, and its path-following state (set once the
    plugins and the path are known to be valid)."""

    def __init__(self, handle: Any) -> None:
        super().__init__(handle, FollowPath.Result())
        self.frame = handle.request.path.header.frame_id
        self.following: PathFollowing | None = None


class ControllerServer(NavLifecycleNode):
    """The ``controller_server`` node; :attr:`costmap_node` must be spun by the same executor."""

    def __init__(self, costmap_node: CostmapROS | None = None, **kwargs: Any) -> None:
        super().__init__("controller_server", **kwargs)
        self.costmap_node = costmap_node or CostmapROS(
            "local_costmap", defaults=CostmapParams.local_defaults(), **kwargs)
        self._current: _PathRun | None = None
        self._velocity = Twist2D(0.0, 0.0)
        self._speed = 0.0  # m/s, from odometry, for the feedback
        self._active = False
        self._entities: list[Any] = []
        #: what the newest goal kept of the one it preempted (the tests read it; nothing else does)
        self.last_takeover: Takeover | None = None

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, ControllerServerParams)
        run_transition(self.costmap_node, "configure")
        costmap = self.costmap_node.costmap
        assert costmap is not None
        cp = self.costmap_node.params
        body = parse_footprint(p.collision_footprint, self.get_name(), "collision_footprint")
        footprint: Any = PolygonFootprint(cp.footprint) if cp.footprint else CircleFootprint(
            costmap.inscribed_radius, PolygonFootprint(body) if body else None)
        self.plugins: ControllerPlugins = build_plugins(
            self, p.controller_plugins, p.goal_checker_plugins, p.progress_checker_plugins, footprint,
            costmap.inscribed_radius, p.controller_frequency)
        self._param_callbacks = take_param_updates(self, self.plugins.controllers)
        self._cmd = CmdVelPublisher(self, p.enable_stamped_cmd_vel, cp.robot_base_frame)
        self._pub_local_plan = self.create_publisher(Path, "local_plan", DEFAULT)
        self._mppi_visualization = MPPIVisualization(self, self.plugins.controllers)
        self._selectors = [Selector(self, "controller_selector"), Selector(self, "goal_checker_selector")]
        self._odom_sub = self.create_subscription(Odometry, p.odom_topic, self._on_odom, DEFAULT)
        self._response = ResponseMonitor(self, p.response_timeout, p.battery_topic)
        self._server = ActionServer(self, FollowPath, "follow_path", self._execute,
                                    goal_callback=self._accept_goal, cancel_callback=self._cancel,
                                    result_timeout=round(p.action_server_result_timeout))

    def activate(self) -> None:
        run_transition(self.costmap_node, "activate")
        self._timer = create_periodic_timer(self, 1.0 / self.params.controller_frequency, self._cycle)
        self._active = True

    def deactivate(self) -> None:
        self._active = False
        self.destroy_timer(self._timer)
        if self._current is not None:
            self._current.finish(Outcome.ABORTED, Code.UNKNOWN, "controller_server deactivated")
            self._current = None
        self._cmd.stop()
        run_transition(self.costmap_node, "deactivate")

    def cleanup(self) -> None:
        for callback in self._param_callbacks:
            self.remove_on_set_parameters_callback(callback)
        self._server.destroy()
        for selector in self._selectors:
            selector.destroy()
        self.destroy_subscription(self._odom_sub)
        self._response.destroy()
        self.destroy_publisher(self._pub_local_plan)
        self._mppi_visualization.destroy()
        self._cmd.destroy()
        run_transition(self.costmap_node, "cleanup")

    # -- action callbacks --------------------------------------------------------------------------
    def _accept_goal(self, goal: Any) -> GoalResponse:
        return GoalResponse.ACCEPT if self._active else GoalResponse.REJECT

    def _on_odom(self, msg: Odometry) -> None:
        p, twist = self.params, msg.twist.twist
        vx = twist.linear.x if abs(twist.linear.x) >= p.min_x_velocity_threshold else 0.0
        wz = twist.angular.z if abs(twist.angular.z) >= p.min_theta_velocity_threshold else 0.0
        self._velocity = Twist2D(vx, wz)
        self._speed = math.hypot(twist.linear.x, twist.linear.y)
        self._response.odometry_received(self._now())

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    async def _execute(self, handle: Any) -> FollowPath.Result:
        goal = handle.request
        controller_sel, checker_sel = self._selectors
        p = self.params
        ids = (controller_sel.resolve(goal.controller_id, p.controller_plugins[0]),
               checker_sel.resolve(goal.goal_checker_id, p.goal_checker_plugins[0]),
               goal.progress_checker_id or p.progress_checker_plugins[0])
        run = _PathRun(handle)
        try:
            plugins = self._plugins(ids)
            run.following = following = PathFollowing(ids, path_to_array(goal.path))
        except ControllerError as error:
            run.finish(Outcome.ABORTED, error.code, error.message)
            return await run.wait()
        old = self._current
        previous = old.following if old is not None and not old.finished else None
        if old is not None:
            old.finish(Outcome.ABORTED, Code.NONE, "preempted by a newer goal")
        takeover = self.last_takeover = following.take_over(previous, plugins, p.path_reuse_tolerance)
        if takeover is Takeover.FRESH:
            self._response.reset()
        self._current = run
        self.get_logger().info(f"following a path of {len(goal.path.poses)} poses with '{ids[0]}'"
                               + _TAKEOVER_NOTES[takeover])
        return await run.wait()

    def _plugins(self, ids: tuple[str, str, str]) -> Plugins:
        sets: tuple[Mapping[str, Any], ...] = (
            self.plugins.controllers, self.plugins.goal_checkers, self.plugins.progress_checkers
        )
        for plugin_id, plugins, kind in zip(ids, sets, ("controller", "goal checker", "progress checker"),
                                            strict=True):
            if plugin_id not in plugins:
                raise InvalidController(f"{kind} id '{plugin_id}' is not one of {sorted(plugins)}")
        return Plugins(*(s[i] for s, i in zip(sets, ids, strict=True)))

    def _cancel(self, handle: Any) -> CancelResponse:
        return cancel_current(self._current, handle, self._cmd.stop)

    # -- the control cycle -------------------------------------------------------------------------
    def _cycle(self) -> None:
        run = self._current
        if run is None or run.finished:
            self._current = None   # idle: the timer keeps running so its grid never shifts
            return
        if run.stop_requested:
            if run.handle.is_cancel_requested:
                self._end(run, Outcome.CANCELED, Code.NONE, "canceled")
            return
        try:
            self._control(run)
        except ControllerError as error:
            self._end(run, Outcome.ABORTED, error.code, error.message)
        except FrameError as error:
            self._end(run, Outcome.ABORTED, Code.TF_ERROR, str(error))
        except Exception as error:  # a plugin bug must become UNKNOWN, never kill the server
            self.get_logger().error(f"controller failed: {type(error).__name__}: {error}")
            self._end(run, Outcome.ABORTED, Code.UNKNOWN, f"{type(error).__name__}: {error}")

    def _end(self, run: _PathRun, outcome: Outcome, code: int, message: str) -> None:
        self._cmd.stop()
        if outcome is not Outcome.SUCCEEDED:
            self.get_logger().warn(f"follow_path {outcome.value} ({code}): {message}")
        run.finish(outcome, code, message if outcome is not Outcome.SUCCEEDED else "")
        self._current = None

    def _control(self, run: _PathRun) -> None:
        """Look up what the cycle needs, let the goal's PathFollowing decide, and apply the decision."""
        following = run.following
        assert following is not None
        snap = self.costmap_node.snapshot()
        frames = self.costmap_node.frames
        cycle_ns = nominal_call_ns(self, self._timer)  # the cycle's slot on the timer's grid
        now = cycle_ns * 1e-9
        if snap is None or frames is None or not self.costmap_node.current:
            decision = following.without_costmap(now, snap is None, self.params.costmap_update_timeout)
        else:
            local_frame = self.costmap_node.global_frame
            cycle = CycleInputs(now, frames.robot_pose(run.frame), frames.robot_pose(local_frame),
                                frames.frame_pose(local_frame, run.frame), self._velocity, CostGrid(*snap))
            decision = following.step(cycle, self._plugins(following.ids), self.params.failure_tolerance,
                                      self._response.stillness_note)
        if decision.action is Action.HOLD:
            self._cmd.stop()
        elif decision.action is Action.SUCCEED:
            self.get_logger().info(f"goal {tuple(round(v, 3) for v in following.handler.goal)} reached at "
                                   f"{tuple(round(v, 3) for v in cycle.robot)} ({run.frame})")
            self._end(run, Outcome.SUCCEEDED, Code.NONE, "")
        elif decision.action is Action.ABORT:
            self._end(run, Outcome.ABORTED, decision.code, decision.message)
        else:
            self._drive(run, decision, cycle_ns)

    def _drive(self, run: _PathRun, decision: Decision, cycle_ns: int) -> None:
        """Publish a DRIVE decision's command, the controller's trajectory and the goal's feedback."""
        cmd = decision.cmd
        self._response.check(cmd, self._velocity, self._now())  # odometry is timed at arrival, by _now
        self._cmd.publish(cmd.vx, cmd.wz, cycle_ns)
        controller = self.plugins.controllers[run.following.ids[0]]  # type: ignore[union-attr]
        trajectory = getattr(controller, "last_trajectory", None)
        if trajectory is not None and len(trajectory):
            local_frame = self.costmap_node.global_frame
            stamp = self.get_clock().now().to_msg()
            self._pub_local_plan.publish(path_from_array(trajectory, local_frame, stamp))
            self._mppi_visualization.publish(controller, local_frame, stamp)
        feedback = FollowPath.Feedback()
        feedback.distance_to_goal = decision.distance_to_goal
        feedback.speed = float(self._speed)
        run.handle.publish_feedback(feedback)


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """controller_server and its local_costmap node, ready to add to one executor."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    server = ControllerServer(**kwargs)
    return [server, server.costmap_node]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.control.controller_server [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role="controller_server")


if __name__ == "__main__":
    raise SystemExit(main())
