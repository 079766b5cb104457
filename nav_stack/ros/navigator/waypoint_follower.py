"""waypoint_follower: follow_waypoints by sending NavigateToPose goals one after another (Nav2 Jazzy).

Lifecycle node ``waypoint_follower``. For each pose from ``goal_index`` (``number_of_loops`` extra
passes over the whole list) it sends a NavigateToPose goal to ``navigate_to_pose``, publishes
feedback ``current_waypoint``, and on arrival runs the wait-at-waypoint task
(``wait_at_waypoint.waypoint_pause_duration`` ms of node time, i.e. sim time). A waypoint whose
navigation fails becomes a MissedWaypoint (index, pose, NavigateToPose error_code); with
``stop_on_failure`` the goal aborts with STOP_ON_MISSED_WAYPOINT (603), otherwise the follower goes
on and succeeds with the missed list. Cancel cancels the running navigation.

The execute callback is a coroutine: it awaits its futures, looking at them (and at a cancel)
every ``1 / loop_rate`` s of node time, so the executor thread keeps serving meanwhile. The wait for
the navigator to appear is bounded by SERVER_WAIT s of wall time (a safety net) and happens until
the navigator has been seen once: rmw_fastrtps calls a server unavailable whenever the graph holds
unequal numbers of request readers and response writers for its services (another navigator coming
or going), so asking again before every waypoint would miss waypoints to a passing glitch. A goal
the navigator does not acknowledge is sent again (ros_tools.runtime.actions.acknowledged), SENDS
copies at most, since a request or its answer can be lost while DDS completes a match.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from action_msgs.msg import GoalStatus
from nav2_msgs.action import FollowWaypoints, NavigateToPose
from nav2_msgs.msg import MissedWaypoint
from rclpy.action import ActionClient, CancelResponse, GoalResponse
from rclpy.node import Node

from nav_stack.ros.common.node_runner import run, with_sim_time
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.lifecycle.node import NavLifecycleNode
from ros_tools.runtime.actions import ActionServer, acknowledged
from ros_tools.runtime.waiting import sleep

Result = FollowWaypoints.Result
SERVER_WAIT = 5.0  # s (wall) to wait for navigate_to_pose to appear, or to answer a cancel
SENDS = 3  # copies of a NavigateToPose goal (actions.ACK_RETRY_S apart) before the waypoint is missed


@dataclass(frozen=True)
class WaypointFollowerParams:
    """waypoint_follower parameters (Nav2 Jazzy names; code defaults)."""

    stop_on_failure: bool = True
    loop_rate: float = 20.0  # Hz at which the running navigation is polled
    global_frame_id: str = "map"
    action_server_result_timeout: float = 900.0  # s

    def __post_init__(self) -> None:
        if self.loop_rate <= 0.0:
            raise ValueError(f"loop_rate must be > 0 Hz, got {self.loop_rate}")


@dataclass(frozen=True)
class WaitAtWaypointParams:
    """The wait-at-waypoint task (``wait_at_waypoint.*``): pause after each reached waypoint."""

    enabled: bool = True
    waypoint_pause_duration: int = 0  # ms of node time

    def __post_init__(self) -> None:
        if self.waypoint_pause_duration < 0:
            raise ValueError(f"waypoint_pause_duration must be >= 0 ms, got {self.waypoint_pause_duration}")


class CanceledError(Exception):
    """The follow_waypoints goal was canceled while waiting."""


class WaypointFollower(NavLifecycleNode):
    """The ``waypoint_follower`` lifecycle node."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("waypoint_follower", **kwargs)
        self._active = False
        self._server: ActionServer | None = None
        self._navigator_seen = False  # navigate_to_pose was discovered once (see the module doc)

    def configure(self) -> None:
        self.params = declare_dataclass(self, WaypointFollowerParams)
        self.wait_params = declare_dataclass(self, WaitAtWaypointParams, "wait_at_waypoint.")
        self._nav = ActionClient(self, NavigateToPose, "navigate_to_pose")
        self._navigator_seen = False
        self._server = ActionServer(
            self, FollowWaypoints, "follow_waypoints", self._execute,
            goal_callback=lambda _goal: GoalResponse.ACCEPT if self._active else GoalResponse.REJECT,
            cancel_callback=lambda _handle: CancelResponse.ACCEPT,
            result_timeout=int(self.params.action_server_result_timeout))

    def activate(self) -> None:
        self._active = True

    def deactivate(self) -> None:
        self._active = False

    def cleanup(self) -> None:
        if self._server is not None:
            self._server.destroy()
            self._nav.destroy()
            self._server = None

    # -- execution ---------------------------------------------------------------------------------
    async def _poll(self, handle: Any, done: Any, timeout: float | None = None) -> bool:
        """Wait until ``done()`` (True) or ``timeout`` s of wall time (False).

        Raises:
            CanceledError: the goal was canceled, or the node deactivated, while waiting.
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        while not done():
            if handle.is_cancel_requested or not self._active or not self.context.ok():
                raise CanceledError
            if deadline is not None and time.monotonic() > deadline:
                return False
            await sleep(self, 1.0 / self.params.loop_rate)
        return True

    async def _navigate(self, handle: Any, pose: Any) -> tuple[bool, int, str]:
        """Navigate to ``pose``: (reached, error_code, error_msg)."""
        if not self._navigator_seen:
            if not await self._poll(handle, self._nav.server_is_ready, SERVER_WAIT):
                return False, Result.UNKNOWN, "navigate_to_pose is not available"
            self._navigator_seen = True
        wanted = lambda: not handle.is_cancel_requested and self._active  # noqa: E731
        sent = await acknowledged(self, self._nav, NavigateToPose.Goal(pose=pose), SENDS, wanted)
        if sent is None:
            if not wanted():
                raise CanceledError
            return False, Result.UNKNOWN, f"navigate_to_pose acknowledged none of {SENDS} copies of the goal"
        nav_handle = sent.result()
        if not nav_handle.accepted:
            return False, Result.UNKNOWN, "navigate_to_pose rejected the goal"
        outcome = nav_handle.get_result_async()
        try:
            await self._poll(handle, outcome.done)
        except CanceledError:
            cancel = nav_handle.cancel_goal_async()
            deadline = time.monotonic() + SERVER_WAIT
            while not (cancel.done() and outcome.done()) and time.monotonic() < deadline:
                await sleep(self, 1.0 / self.params.loop_rate)
            raise
        response = outcome.result()
        reached = response.status == GoalStatus.STATUS_SUCCEEDED
        return reached, int(response.result.error_code), str(response.result.error_msg)

    async def _pause(self, handle: Any) -> None:
        if not self.wait_params.enabled or self.wait_params.waypoint_pause_duration <= 0:
            return
        clock = self.get_clock()
        until = clock.now().nanoseconds + self.wait_params.waypoint_pause_duration * 1_000_000
        await self._poll(handle, lambda: clock.now().nanoseconds >= until)

    async def _execute(self, handle: Any) -> Any:
        goal = handle.request
        result = Result()
        poses = list(goal.poses)
        if not poses or goal.goal_index >= len(poses):
            result.error_code = Result.NO_VALID_WAYPOINTS
            result.error_msg = (f"no waypoints to follow: {len(poses)} poses, goal_index {goal.goal_index}")
            handle.abort()
            return result
        self.get_logger().info(f"Received follow waypoint request with {len(poses)} waypoints")
        start = int(goal.goal_index)
        try:
            for loop in range(int(goal.number_of_loops) + 1):
                for index in range(start if loop == 0 else 0, len(poses)):
                    handle.publish_feedback(FollowWaypoints.Feedback(current_waypoint=index))
                    reached, code, message = await self._navigate(handle, poses[index])
                    if reached:
                        self.get_logger().info(f"Succeeded processing waypoint {index}")
                        await self._pause(handle)
                        continue
                    self.get_logger().warn(f"Failed to process waypoint {index}: {message or code}")
                    missed = MissedWaypoint(index=index, goal=poses[index], error_code=code)
                    result.missed_waypoints.append(missed)
                    if self.params.stop_on_failure:
                        result.error_code = Result.STOP_ON_MISSED_WAYPOINT
                        result.error_msg = f"waypoint {index} failed ({code}): {message} (stop_on_failure)"
                        handle.abort()
                        return result
        except CanceledError:
            if handle.is_cancel_requested:
                handle.canceled()
            else:
                result.error_msg = "waypoint_follower was deactivated"
                handle.abort()
            return result
        handle.succeed()
        return result


def build_nodes(use_sim_time: bool = False, **kwargs: Any) -> list[Node]:
    """The waypoint_follower node (``kwargs`` go to its constructor)."""
    kwargs = with_sim_time(kwargs, use_sim_time)
    return [WaypointFollower(**kwargs)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m nav_stack.ros.navigator.waypoint_follower [--autostart] [--ros-args ...]``."""
    return run(build_nodes, argv, role="waypoint_follower")


if __name__ == "__main__":
    raise SystemExit(main())
