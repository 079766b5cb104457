"""behavior_server: spin, backup, drive_on_heading, assisted_teleop and wait (Nav2 Jazzy names and codes).

Each behavior is a core state machine stepped at ``cycle_frequency`` by a timer on the node clock
(sim time in simulation) with the robot pose in ``local_frame`` from TF. Like Nav2's behaviors, the
motion ones check ``simulate_ahead_time`` s of the commanded motion against the local costmap,
received as ``local_costmap/costmap_raw`` with the robot outline from
``local_costmap/published_footprint`` (converted to the robot frame when a goal starts; a 0.22 m
circle until one arrives), and end with COLLISION_AHEAD. TIMEOUT after ``time_allowance``,
TF_ERROR when the pose is unknown, INVALID_INPUT for BackUp/DriveOnHeading targets off the x axis.

AssistedTeleop forwards the last command heard on ``cmd_vel_teleop`` (Twist, or TwistStamped with
``enable_stamped_cmd_vel``) to cmd_vel, scaled down so that ``projection_time`` s of it, checked every
``simulation_time_step`` s, stay clear of the local costmap (nav_stack.core.behaviors.assisted_teleop);
a message on ``preempt_teleop`` (std_msgs/Empty) ends it with success, ``time_allowance`` with TIMEOUT.

One behavior runs at a time (they share cmd_vel): a new goal of any behavior aborts the running
one. A cancel publishes a zero command at once; every end publishes a zero command.

Time: a cycle works at its nominal time, its slot on the timer's grid (ros_tools.runtime.timers.
nominal_call_ns), not at the clock's "now", which under lockstep has moved on by a /clock message or
two depending on wall timing. Its commands carry that time as their stamp, so a stamped cmd_vel
takes effect at the same sim time on every run (docs/architecture.md, "What repeats"). The timer
therefore runs from activation to deactivation, never reset: a reset at a goal's arrival would put
the grid where the goal happened to arrive.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from geometry_msgs.msg import PolygonStamped, Twist, TwistStamped
from nav2_msgs.action import AssistedTeleop, BackUp, DriveOnHeading, Spin, Wait
from nav2_msgs.msg import Costmap
from rclpy.action import CancelResponse, GoalResponse
from rclpy.node import Node
from std_msgs.msg import Empty

from nav_stack.core import behaviors
from nav_stack.core.behaviors import BehaviorParams, BehaviorResult
from nav_stack.core.control import CircleFootprint, CostGrid, PolygonFootprint
from nav_stack.core.geometry import to_frame
from nav_stack.ros.bringup.param_layout import param
from nav_stack.ros.common.conversions import duration_msg, duration_to_seconds, spec_from_info
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.common.goal_runs import GoalRun, Outcome, cancel_current
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import DEFAULT, LATCHED
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.cmd_vel import CMD_VEL_QOS, CmdVelPublisher
from ros_tools.runtime.actions import RESULT_TIMEOUT_S, ActionServer
from ros_tools.runtime.timers import create_periodic_timer, nominal_call_ns

#: plugin type -> (action type, TF_ERROR code)
BEHAVIOR_TYPES: dict[str, tuple[Any, int]] = {
    "Spin": (Spin, int(behaviors.SpinErrorCode.TF_ERROR)),
    "BackUp": (BackUp, int(behaviors.BackUpErrorCode.TF_ERROR)),
    "DriveOnHeading": (DriveOnHeading, int(behaviors.DriveOnHeadingErrorCode.TF_ERROR)),
    "AssistedTeleop": (AssistedTeleop, int(behaviors.AssistedTeleopErrorCode.TF_ERROR)),
    "Wait": (Wait, 0),
}
DEFAULT_TYPES = {"spin": "Spin", "backup": "BackUp", "drive_on_heading": "DriveOnHeading",
                 "assisted_teleop": "AssistedTeleop", "wait": "Wait"}


@dataclass(frozen=True)
class BehaviorServerParams:
    """behavior_server knobs besides the core's BehaviorParams (Jazzy yaml values)."""

    behavior_plugins: tuple[str, ...] = ("spin", "backup", "drive_on_heading", "wait")
    local_frame: str = "odom"
    global_frame: str = "map"
    robot_base_frame: str = "base_link"
    transform_tolerance: float = 0.1
    local_costmap_topic: str = "local_costmap/costmap_raw"
    local_footprint_topic: str = "local_costmap/published_footprint"
    enable_stamped_cmd_vel: bool = False
    action_server_result_timeout: float = RESULT_TIMEOUT_S  # s a finished goal's result is kept


class _BehaviorRun(GoalRun):
    def __init__(self, handle: Any, result: Any, behavior: Any, kind: str, tf_error: int) -> None:
        super().__init__(handle, result)
        self.behavior, self.kind, self.tf_error = behavior, kind, tf_error


class BehaviorServer(NavLifecycleNode):
    """The ``behavior_server`` node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("behavior_server", **kwargs)
        self._current: _BehaviorRun | None = None
        self._grid: CostGrid | None = None
        self._footprint_msg: PolygonStamped | None = None
        self._teleops: dict[str, behaviors.AssistedTeleop] = {}  # per plugin id, kept across goals as Nav2's
        self._active = False

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, BehaviorServerParams)
        self.behavior_params = declare_dataclass(self, BehaviorParams)
        self.frames = Frames(self, p.robot_base_frame)
        self._cmd = CmdVelPublisher(self, p.enable_stamped_cmd_vel, p.robot_base_frame)
        self._subs = [
            self.create_subscription(Costmap, p.local_costmap_topic, self._on_costmap, LATCHED),
            self.create_subscription(PolygonStamped, p.local_footprint_topic, self._on_footprint, LATCHED),
        ]
        self._servers = []
        for name in p.behavior_plugins:
            plugin = str(param(self, f"{name}.plugin", f"nav2_behaviors::{DEFAULT_TYPES.get(name, '')}"))
            kind = plugin.replace("/", "::").split("::")[-1]
            if kind not in BEHAVIOR_TYPES:
                raise ValueError(f"behavior_server: {name}.plugin '{plugin}' is not one of "
                                 f"{sorted(BEHAVIOR_TYPES)}")
            action_type, tf_error = BEHAVIOR_TYPES[kind]
            if kind == "AssistedTeleop":
                self._add_teleop(name)
            self._servers.append(ActionServer(
                self, action_type, name, partial(self._execute, kind=kind, tf_error=tf_error, name=name),
                goal_callback=self._accept_goal, cancel_callback=self._cancel,
                result_timeout=round(p.action_server_result_timeout)))

    def _add_teleop(self, name: str) -> None:
        """The AssistedTeleop of plugin ``name``; the first one also declares the node-level parameters
        (Nav2's names, shared by every AssistedTeleop) and subscribes to the operator's topics."""
        if not self._teleops:
            self._teleop_params = declare_dataclass(self, behaviors.AssistedTeleopParams)
            twist_type = TwistStamped if self.params.enable_stamped_cmd_vel else Twist
            topic = str(param(self, "cmd_vel_teleop", "cmd_vel_teleop"))
            self._subs += [
                self.create_subscription(twist_type, topic, self._on_teleop, CMD_VEL_QOS),
                self.create_subscription(Empty, "preempt_teleop", self._on_preempt_teleop, DEFAULT),
            ]
        self._teleops[name] = behaviors.AssistedTeleop(self._teleop_params)

    def activate(self) -> None:
        self._timer = create_periodic_timer(self, 1.0 / self.behavior_params.cycle_frequency, self._cycle)
        self._active = True

    def deactivate(self) -> None:
        self._active = False
        self.destroy_timer(self._timer)
        if self._current is not None:
            self._release(self._current, "behavior_server deactivated")
            self._current = None
        self._cmd.stop()

    def cleanup(self) -> None:
        for server in self._servers:
            server.destroy()
        for sub in self._subs:
            self.destroy_subscription(sub)
        self._teleops = {}
        self._cmd.destroy()
        self.frames.destroy()

    # -- inputs ------------------------------------------------------------------------------------
    def _on_costmap(self, msg: Costmap) -> None:
        if msg.header.frame_id.lstrip("/") != self.params.local_frame:
            self.get_logger().warn(f"ignoring a costmap in frame '{msg.header.frame_id}', expected "
                                   f"'{self.params.local_frame}'", throttle_duration_sec=10.0)
            return
        spec = spec_from_info(msg.metadata)
        self._grid = CostGrid(np.frombuffer(msg.data, dtype=np.uint8).reshape(spec.shape).copy(), spec)

    def _on_footprint(self, msg: PolygonStamped) -> None:
        self._footprint_msg = msg

    def _on_teleop(self, msg: Twist | TwistStamped) -> None:
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        for teleop in self._teleops.values():
            teleop.teleop(behaviors.TeleopCommand(twist.linear.x, twist.linear.y, twist.angular.z))

    def _on_preempt_teleop(self, msg: Empty) -> None:
        for teleop in self._teleops.values():
            teleop.preempt()

    def _footprint(self) -> Any:
        """The robot outline in the robot frame, from the last published footprint (Nav2's way)."""
        msg = self._footprint_msg
        if msg is None or len(msg.polygon.points) < 3:
            return CircleFootprint()
        try:
            robot = self.frames.robot_pose(msg.header.frame_id)
        except FrameError:
            return CircleFootprint()
        pts = np.array([(p.x, p.y, 0.0) for p in msg.polygon.points])
        local = to_frame(pts, robot)
        return PolygonFootprint(tuple((float(x), float(y)) for x, y in local[:, :2]))

    # -- goals -------------------------------------------------------------------------------------
    def _accept_goal(self, goal: Any) -> GoalResponse:
        return GoalResponse.ACCEPT if self._active else GoalResponse.REJECT

    def _now(self) -> float:
        return float(self.get_clock().now().nanoseconds * 1e-9)

    def _start(self, handle: Any, kind: str, tf_error: int, name: str) -> _BehaviorRun:
        goal, action_type = handle.request, BEHAVIOR_TYPES[kind][0]
        params = self.behavior_params
        if kind == "AssistedTeleop":
            teleop = self._teleops[name]
            teleop.start(duration_to_seconds(goal.time_allowance), self._now(), self._footprint())
            return _BehaviorRun(handle, action_type.Result(), teleop, kind, tf_error)
        if kind == "Wait":
            behavior: Any = behaviors.Wait()
            run = _BehaviorRun(handle, action_type.Result(), behavior, kind, tf_error)
            refused = behavior.start(duration_to_seconds(goal.time), self._now())
        else:
            footprint = self._footprint()
            if kind == "Spin":
                behavior = behaviors.Spin(params, footprint)
                core_goal: Any = behaviors.SpinGoal(goal.target_yaw, duration_to_seconds(goal.time_allowance))
            else:
                drive = behaviors.BackUp if kind == "BackUp" else behaviors.DriveOnHeading
                behavior = drive(params, footprint)
                core_goal = behaviors.DriveGoal(goal.target.x, goal.speed,
                                                duration_to_seconds(goal.time_allowance), goal.target.y,
                                                goal.target.z)
            run = _BehaviorRun(handle, action_type.Result(), behavior, kind, tf_error)
            try:
                pose = self.frames.robot_pose(self.params.local_frame)
            except FrameError as error:
                run.finish(Outcome.ABORTED, tf_error, str(error))
                return run
            refused = behavior.start(core_goal, pose, self._now())
        if refused is not None:
            run.finish(Outcome.ABORTED, refused.error_code, refused.error_msg)
        return run

    async def _execute(self, handle: Any, kind: str, tf_error: int, name: str = "") -> Any:
        run = self._start(handle, kind, tf_error, name)
        if not run.finished:
            if self._current is not None:
                self._release(self._current, f"preempted by a new {kind} goal", successor=run)
            self._current = run
            self.get_logger().info(f"running {kind}")
        return await run.wait()

    def _release(self, run: _BehaviorRun, reason: str, successor: _BehaviorRun | None = None) -> None:
        """Abort a run that did not end by itself (error code 0, ``reason``); an AssistedTeleop forgets
        its command unless the goal that takes over is another goal of the same plugin."""
        if run.kind == "AssistedTeleop" and (successor is None or successor.behavior is not run.behavior):
            run.behavior.finish()
        run.finish(Outcome.ABORTED, 0, reason)

    def _cancel(self, handle: Any) -> CancelResponse:
        return cancel_current(self._current, handle, self._cmd.stop)

    # -- the cycle ---------------------------------------------------------------------------------
    def _cycle(self) -> None:
        run = self._current
        if run is None or run.finished:
            self._current = None
            return
        cycle_ns = nominal_call_ns(self, self._timer)  # the cycle's slot on the timer's grid
        if run.stop_requested:
            if run.handle.is_cancel_requested:
                self._end(run, Outcome.CANCELED, BehaviorResult(0, "canceled", 0.0), cycle_ns)
            return
        now = cycle_ns * 1e-9
        if run.kind == "AssistedTeleop":
            self._teleop_cycle(run, cycle_ns)
            return
        if run.kind == "Wait":
            outcome = run.behavior.step(now)
            run.handle.publish_feedback(Wait.Feedback(time_left=duration_msg(run.behavior.time_left)))
            if outcome is not None:
                self._end(run, Outcome.SUCCEEDED, outcome, cycle_ns)
            return
        try:
            pose = self.frames.robot_pose(self.params.local_frame)
        except FrameError as error:
            self._end(run, Outcome.ABORTED, BehaviorResult(run.tf_error, str(error), 0.0), cycle_ns)
            return
        step = run.behavior.step(pose, now, self._grid)
        if isinstance(step, BehaviorResult):
            self._end(run, Outcome.SUCCEEDED if step.succeeded else Outcome.ABORTED, step, cycle_ns)
            return
        self._cmd.publish(step.vx, step.wz, cycle_ns)
        self._feedback(run)

    def _teleop_cycle(self, run: _BehaviorRun, cycle_ns: int) -> None:
        """Nav2's order: feedback, end (time allowance, preempt), pose, the scaled command."""
        teleop = run.behavior
        end = teleop.check(cycle_ns * 1e-9)
        run.handle.publish_feedback(
            AssistedTeleop.Feedback(current_teleop_duration=duration_msg(teleop.current_teleop_duration)))
        if end is not None:
            self._end(run, Outcome.SUCCEEDED if end.succeeded else Outcome.ABORTED, end, cycle_ns)
            return
        try:
            pose = self.frames.robot_pose(self.params.local_frame)
        except FrameError as error:
            self._end(run, Outcome.ABORTED,
                      BehaviorResult(run.tf_error, str(error), teleop.current_teleop_duration), cycle_ns)
            return
        cmd = teleop.command(pose, self._grid)
        self._cmd.publish(cmd.vx, cmd.wz, cycle_ns, vy=cmd.vy)

    def _feedback(self, run: _BehaviorRun) -> None:
        action_type = BEHAVIOR_TYPES[run.kind][0]
        feedback = action_type.Feedback()
        if run.kind == "Spin":
            feedback.angular_distance_traveled = float(run.behavior.angular_distance_traveled)
        else:
            feedback.distance_traveled = float(run.behavior.distance_traveled)
        run.handle.publish_feedback(feedback)

    def _end(self, run: _BehaviorRun, outcome: Outcome, result: BehaviorResult, cycle_ns: int) -> None:
        if run.kind != "Wait":
            self._cmd.stop(cycle_ns)
        if run.kind == "AssistedTeleop":
            run.behavior.finish()
        if outcome is Outcome.ABORTED:
            self.get_logger().warn(f"{run.kind} failed ({result.error_code}): {result.error_msg}")
        run.result.total_elapsed_time = duration_msg(result.total_elapsed_time)
        run.finish(outcome, result.error_code if outcome is not Outcome.CANCELED else 0,
                   result.error_msg if outcome is Outcome.ABORTED else "")
        self._current = None


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The behavior_server node (a list, like the other servers' ``build_nodes``)."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [BehaviorServer(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.behaviors.behavior_server [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role="behavior_server")


if __name__ == "__main__":
    raise SystemExit(main())
