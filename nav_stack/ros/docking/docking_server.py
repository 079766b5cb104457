"""docking_server: Nav2 Jazzy's opennav_docking server (DockRobot, UndockRobot, ReloadDockDatabase).

Actions ``dock_robot`` (nav2_msgs/action/DockRobot) and ``undock_robot`` (UndockRobot), service
``~/reload_database`` (nav2_msgs/srv/ReloadDockDatabase). The sequences are
nav_stack.core.docking.sequence / .undocking; this node translates goals and results, declares the
parameters (nav_stack.core.docking's dataclasses, ``controller.*``, the plugins' ``<name>.*``, the
dock database) and schedules: each goal's execute coroutine awaits its end while a timer on the node
clock (sim time) ticks the running sequence at ``controller_frequency``. The staging navigation is a
NavigateToPose goal awaited in a coroutine of its own (docking_navigator). Nothing blocks.

Velocity goes to ``cmd_vel`` (nav2_bringup remaps it to ``cmd_vel_nav``), Twist or TwistStamped by
``enable_stamped_cmd_vel`` (stamped with the cycle's nominal time). Every end of a goal commands a
stop; a cancel commands one at once. One goal runs at a time: a new dock or undock goal aborts the
running one (UNKNOWN, "preempted"). After a successful docking the dock's type is remembered, so an
UndockRobot goal without ``dock_type`` undocks from it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from nav2_msgs.action import DockRobot, UndockRobot
from nav2_msgs.srv import ReloadDockDatabase
from rclpy.action import CancelResponse, GoalResponse
from rclpy.node import Node

from nav_stack.core.docking import (
    DockDatabase,
    DockingController,
    DockingControllerParams,
    DockingOutcome,
    DockingResult,
    DockingSequence,
    DockingServerParams,
    DockRequest,
    StagingGoal,
    UndockingSequence,
    UndockRequest,
)
from nav_stack.core.geometry import Pose2D, yaw_or_nan
from nav_stack.ros.bringup.param_layout import build, declare_fields
from nav_stack.ros.common.conversions import duration_msg
from nav_stack.ros.common.frames import Frames
from nav_stack.ros.common.goal_runs import GoalRun, Outcome, cancel_current
from nav_stack.ros.common.node_runner import run as run_nodes
from nav_stack.ros.common.node_runner import with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.docking.docking_navigator import StagingNavigator
from nav_stack.ros.docking.docking_plugins import (
    DockPlugin,
    declare_dynamic,
    docks_from_parameters,
    reload_handler,
)
from nav_stack.ros.docking.docking_world import RosDockingWorld
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.cmd_vel import CmdVelPublisher
from ros_tools.runtime.actions import ActionServer
from ros_tools.runtime.coroutines import spawn
from ros_tools.runtime.timers import create_periodic_timer, nominal_call_ns

NODE_NAME = "docking_server"
DOCK_ROBOT, UNDOCK_ROBOT, RELOAD_SERVICE = "dock_robot", "undock_robot", "~/reload_database"
CONTROLLER_PREFIX = "controller."
OUTCOMES = {DockingOutcome.SUCCEEDED: Outcome.SUCCEEDED, DockingOutcome.ABORTED: Outcome.ABORTED,
            DockingOutcome.CANCELED: Outcome.CANCELED}
UNKNOWN = int(DockRobot.Result.UNKNOWN)


def declare_controller(node: Node) -> DockingControllerParams:
    """``controller.*`` (``lambda`` is the field ``lambda_``)."""
    names = [name for name in DockingControllerParams.__dataclass_fields__ if name != "lambda_"]
    values = declare_fields(node, DockingControllerParams, names, CONTROLLER_PREFIX)
    default = DockingControllerParams.lambda_
    values["lambda_"] = float(declare_dynamic(node, CONTROLLER_PREFIX + "lambda", default))
    return build(node, DockingControllerParams, values, "controller")  # type: ignore[no-any-return]


class _Run(GoalRun):
    """A dock or undock goal and the sequence the timer ticks for it."""

    def __init__(self, handle: Any, result: Any, sequence: Any, docking: bool, start: float) -> None:
        super().__init__(handle, result)
        self.sequence, self.docking, self.start = sequence, docking, start


class DockingServer(NavLifecycleNode):
    """The ``docking_server`` lifecycle node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(NODE_NAME, **kwargs)
        self._current: _Run | None = None
        self._active = False
        self._timer: Any = None
        self._docked_type = ""  # the plugin of the last successful docking, for UndockRobot

    # -- lifecycle ---------------------------------------------------------------------------------
    def configure(self) -> None:
        p = self.params = declare_dataclass(self, DockingServerParams)
        self.controller_params = declare_controller(self)
        names = [str(name) for name in declare_dynamic(self, "dock_plugins", [])]
        if not names:
            raise ValueError(f"{self.get_name()}: dock_plugins is empty; give at least one dock plugin")
        plugins: dict[str, DockPlugin] = {}
        try:
            for name in names:
                plugins[name] = DockPlugin(self, name)
            docks = docks_from_parameters(self)
        except Exception:
            for plugin in plugins.values():
                plugin.destroy()
            raise
        self._plugins = plugins
        if docks is None:
            self.get_logger().warn("Neither dock_database nor docks is set: docking works by dock pose only, "
                                   "until reload_database loads a dock file")
        self.database = DockDatabase({name: plugin.dock for name, plugin in plugins.items()}, docks or {})
        self.frames = Frames(self, p.base_frame)
        self.world = RosDockingWorld(self, self.frames, self.controller_params)
        self.controller = DockingController(self.controller_params)
        self._navigator = StagingNavigator(self, p.navigator_bt_xml)
        self._cmd = CmdVelPublisher(self, p.enable_stamped_cmd_vel, p.base_frame)
        keep = round(p.action_server_result_timeout)
        self._servers = [
            ActionServer(self, DockRobot, DOCK_ROBOT, self._execute_dock, goal_callback=self._accept,
                         cancel_callback=self._cancel, result_timeout=keep),
            ActionServer(self, UndockRobot, UNDOCK_ROBOT, self._execute_undock, goal_callback=self._accept,
                         cancel_callback=self._cancel, result_timeout=keep)]
        self._reload = self.create_service(ReloadDockDatabase, RELOAD_SERVICE, reload_handler(
            self, self.database, lambda: self._current is not None))
        self.get_logger().info(f"Docking Server has {len(plugins)} dock types and "
                               f"{len(self.database.instances)} dock instances available")

    def activate(self) -> None:
        self._timer = create_periodic_timer(self, 1.0 / self.params.controller_frequency, self._cycle)
        self._active = True

    def deactivate(self) -> None:
        self._active = False
        if self._current is not None:
            self._abort(self._current, "docking_server deactivated")
        self.destroy_timer(self._timer)
        self._cmd.stop()

    def cleanup(self) -> None:
        for server in self._servers:
            server.destroy()
        self.destroy_service(self._reload)
        for plugin in self._plugins.values():
            plugin.destroy()
        self.world.destroy()
        self._navigator.destroy()
        self._cmd.destroy()
        self.frames.destroy()
        self._docked_type = ""

    # -- goals -------------------------------------------------------------------------------------
    def _now(self) -> float:
        return float(self.get_clock().now().nanoseconds * 1e-9)

    def _accept(self, goal: Any) -> GoalResponse:
        return GoalResponse.ACCEPT if self._active else GoalResponse.REJECT

    def _cancel(self, handle: Any) -> CancelResponse:
        return cancel_current(self._current, handle, self._cmd.stop)

    async def _execute_dock(self, handle: Any) -> Any:
        goal = handle.request
        position, q = goal.dock_pose.pose.position, goal.dock_pose.pose.orientation
        request = DockRequest(bool(goal.use_dock_id), str(goal.dock_id),
                              Pose2D(position.x, position.y, yaw_or_nan(q.x, q.y, q.z, q.w)),
                              str(goal.dock_pose.header.frame_id), str(goal.dock_type),
                              float(goal.max_staging_time), bool(goal.navigate_to_staging_pose))
        where = f"dock '{goal.dock_id}'" if goal.use_dock_id else f"({position.x:.2f}, {position.y:.2f})"
        self.get_logger().info(f"Attempting to dock robot at {where}")
        now = self._now()
        sequence = DockingSequence(request, self.params, self.controller, self.database, self.world, now)
        return await self._serve(_Run(handle, DockRobot.Result(), sequence, True, now))

    async def _execute_undock(self, handle: Any) -> Any:
        goal = handle.request
        now = self._now()
        sequence = UndockingSequence(UndockRequest(str(goal.dock_type), float(goal.max_undocking_time)),
                                     self._docked_type, self.params, self.controller, self.database,
                                     self.world, now)
        kind = goal.dock_type or self._docked_type or "the only"
        self.get_logger().info(f"Attempting to undock robot from {kind} dock type")
        return await self._serve(_Run(handle, UndockRobot.Result(), sequence, False, now))

    async def _serve(self, run: _Run) -> Any:
        if self._current is not None:
            self._abort(self._current, "preempted by a new docking or undocking goal")
        self._current = run
        if self._active:
            self._timer.reset()  # the cycle sleeps while no goal runs
        return await run.wait()

    async def _navigate(self, run: _Run, goal: StagingGoal) -> None:
        succeeded, message = await self._navigator.navigate(goal)
        if not run.finished:
            run.sequence.navigation_finished(succeeded, message)

    # -- the cycle ---------------------------------------------------------------------------------
    def _cycle(self) -> None:
        run = self._current
        if run is None or run.finished:
            self._current = None
            self._timer.cancel()  # idle: no wake-ups until the next goal resets it
            return
        if run.handle.is_cancel_requested:
            run.sequence.cancel()
        now = self._now()
        retries = getattr(run.sequence, "num_retries", 0)
        step = run.sequence.tick(now)
        if step.num_retries > retries and step.result is None:
            self.get_logger().warn(f"Docking failed, will retry ({step.num_retries} of "
                                   f"{self.params.max_retries}): {run.sequence.retry_reason}")
        if step.navigate is not None:
            spawn(self, self._navigate(run, step.navigate))
        if step.cancel_navigation:
            self._navigator.cancel()
        if step.command is not None and (step.result is not None or not run.stop_requested):
            self._cmd.publish(step.command.vx, step.command.wz, nominal_call_ns(self, self._timer))
        self._publish_poses(run)
        if step.result is not None:
            self._end(run, step.result)
        elif run.docking:
            run.handle.publish_feedback(DockRobot.Feedback(state=int(step.state),
                                                           docking_time=duration_msg(now - run.start),
                                                           num_retries=step.num_retries))

    def _publish_poses(self, run: _Run) -> None:
        """The plugin's dock, filtered and staging poses, for visualisation."""
        sequence = run.sequence
        plugin = self._plugins.get(sequence.plugin.name) if sequence.plugin is not None else None
        if plugin is None:
            return
        staging = None
        if sequence.staging is not None:  # docking: in the dock's frame (known by then); undocking: fixed
            staging = (sequence.staging, sequence.dock.frame if run.docking else self.params.fixed_frame)
        plugin.publish_updates(staging, self.get_clock().now().to_msg())

    def _abort(self, run: _Run, message: str) -> None:
        """End ``run`` from outside its sequence (UNKNOWN), stopping the robot and any staging navigation."""
        self._navigator.cancel()
        self._cmd.stop()
        run.result.success = False
        run.finish(Outcome.ABORTED, UNKNOWN, message)
        self._current = None

    def _end(self, run: _Run, result: DockingResult) -> None:
        if result.success:
            self._docked_type = result.dock_type if run.docking else ""
        run.result.success = result.success
        if run.docking:
            run.result.num_retries = result.num_retries
        action = DOCK_ROBOT if run.docking else UNDOCK_ROBOT
        if result.outcome is DockingOutcome.ABORTED:
            self.get_logger().error(f"{action} failed ({int(result.error_code)}): {result.error_msg}")
        else:
            self.get_logger().info(f"{action} {result.outcome.value}")
        run.finish(OUTCOMES[result.outcome], int(result.error_code), result.error_msg)
        self._current = None


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The docking_server node (a list, like the other servers' ``build_nodes``)."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [DockingServer(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.docking.docking_server [--autostart] [--ros-args ...]``."""
    return run_nodes(build_nodes, argv, role=NODE_NAME)


if __name__ == "__main__":
    raise SystemExit(main())
