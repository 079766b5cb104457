"""nav-explore: frontier exploration on the live SLAM map through navigate_to_pose (explore_lite's role).

Why a client and not a server: exploration only chooses goals; SLAM (``slam``) grows /map and the
Nav2 stack (``nav-bringup --slam``) drives. The goal choice is nav_stack.core.exploration.Explorer.

Loop (a sim-time timer on the one executor thread; nothing blocks it: goals are futures with
done-callbacks, and the final save is driven by a steady timer and the map_saver's answer):
  0. first a full turn in place through Nav2's ``spin`` behavior: SLAM integrates a scan only after
     0.2 m / 0.2 rad of motion and needs a few looks before a cell counts as free, so the map of a
     robot that has not moved shows walls but no free space and hence no frontier;
  1. wait for /map (transient local) and the robot pose (TF map → base_footprint);
  2. after a goal ended, wait until a map stamped after that moment arrives (or ``map_wait`` s), so
     the next choice sees what the robot just observed;
  3. ``Explorer.next_goal``: COMPLETE (no reachable frontier of ``min_frontier_size`` left) ends the run
     with "exploration complete"; NO_FREE_SPACE (nothing mapped free within robot_radius of the robot
     yet) waits; otherwise send the goal as NavigateToPose (frame map);
  4. SUCCEEDED → ``mark_reached``; rejected, aborted, canceled or over ``goal_timeout`` → ``mark_failed``
     (explore_lite's blacklist), then back to 1. ``max_time`` sim s ends the run early (exit code 3).
A progress line (goals, mapped area, elapsed sim time) is printed per goal and every ``progress_period``.
``-f NAME`` saves the final map through ``map_saver/save_map`` or, without a map_saver, with
nav_stack.core.map_io (free_thresh 0.196 so unknown stays unknown on reload).
Under ``use_sim_time`` (the default) the process takes part in lockstep as ``explore``, so the
simulator never runs ahead of the goal choice.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from action_msgs.msg import GoalStatus
from nav2_msgs.action import NavigateToPose, Spin
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.action import ActionClient
from rclpy.node import Node

from nav_stack.core.exploration import ExplorationStatus, Explorer, ExplorerParams
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import OccupancyMap, save_map
from nav_stack.ros.common.conversions import duration_msg, grid_from_occupancy, pose_stamped
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.common.params import declare_dataclass
from nav_stack.ros.common.qos import LATCHED
from ros_tools.runtime.timers import create_periodic_timer
from ros_tools.runtime.waiting import steady_clock
from ros_tools.tf.ros import stamp_to_seconds

NAVIGATE_ACTION = "navigate_to_pose"
SPIN_ACTION = "spin"
SPIN_WAIT = 20.0  # s (node clock) to wait for the spin server before exploring without the first turn
SPIN_ALLOWANCE = 60.0  # s the first turn may take; after SPIN_ALLOWANCE + SPIN_WAIT exploring starts anyway
MAP_SAVER_SERVICE = "map_saver/save_map"
TICK_PERIOD = 0.5  # s (node clock) between loop steps
SAVE_FREE_THRESH = 0.196  # keeps pixel 205 unknown on reload (see nav_stack/ros/slam/map_saver.py)
SAVER_DISCOVERY = 2.0  # wall s to find the map_saver service before saving with map_io instead
SAVER_ANSWER = 15.0  # wall s the map_saver may take to answer
SAVER_POLL = 0.05  # wall s between checks while saving (discovery has no event to wait on)
EXIT_TIMEOUT = 3


@dataclass(frozen=True)
class ExploreParams:
    """Run knobs (s of the node clock, sim time under use_sim_time).

    Attributes:
        max_time: the run stops after this long even with frontiers left (explore_lite has no limit).
        goal_timeout: a goal still running after this long is canceled and blacklisted.
        map_wait: longest wait for a map newer than the end of the last goal.
        progress_period: a progress line at least this often.
        global_frame / robot_base_frame: goal frame and the robot frame looked up in it.
    """

    max_time: float = 900.0
    goal_timeout: float = 120.0
    map_wait: float = 6.0
    progress_period: float = 15.0
    global_frame: str = "map"
    robot_base_frame: str = "base_footprint"


class ExploreNode(Node):
    """Chooses frontier goals and sends them; ``finished`` / ``exit_code`` say when and how it ended.

    Args:
        map_file: when given, the run ends by saving the map as ``map_file``.pgm/.yaml (``finished``
            is set once the map is saved or the save failed; a failed save makes ``exit_code`` 1).
    """

    def __init__(self, map_file: str | None = None, **kwargs: Any) -> None:
        super().__init__("explore", **kwargs)
        self.map_file = map_file
        self.params = declare_dataclass(self, ExploreParams)
        self.explorer = Explorer(declare_dataclass(self, ExplorerParams))
        self.frames = Frames(self, self.params.robot_base_frame)
        self.map: tuple[np.ndarray, GridSpec, float] | None = None  # data, spec, stamp (s)
        self.map_msg: OccupancyGrid | None = None
        self.finished = False
        self.exit_code = 0
        self.summary = ""
        self.goals = self.reached = self.failed = 0
        self._client = ActionClient(self, NavigateToPose, NAVIGATE_ACTION)
        self._spin_client = ActionClient(self, Spin, SPIN_ACTION)
        self._spin = "todo"  # todo -> running -> done
        self._goal: Pose2D | None = None
        self._handle: Any = None
        self._goal_started = 0.0
        self._ended_at = -math.inf
        self._started: float | None = None
        self._last_progress = -math.inf
        self._ending = False  # the run has ended and the map is being saved
        self.create_subscription(OccupancyGrid, "map", self._on_map, LATCHED)
        self._timer = create_periodic_timer(self, TICK_PERIOD, self._step)

    def now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _on_map(self, msg: OccupancyGrid) -> None:
        data, spec = grid_from_occupancy(msg)
        self.map, self.map_msg = (data, spec, stamp_to_seconds(msg.header.stamp)), msg

    def mapped_area(self) -> float:
        """Known (free or occupied) area of the current map (m²)."""
        if self.map is None:
            return 0.0
        data, spec, _ = self.map
        return float((data >= 0).sum()) * spec.resolution**2

    def progress(self, what: str) -> str:
        elapsed = 0.0 if self._started is None else self.now() - self._started
        line = (f"explore: {what} | goals {self.goals} (reached {self.reached}, failed {self.failed}) | "
                f"mapped {self.mapped_area():.1f} m2 | {elapsed:.1f} sim s")
        print(line, flush=True)
        self._last_progress = self.now()
        return line

    # -- the loop ------------------------------------------------------------------------------
    def _step(self) -> None:
        if self._ending or self.map is None:
            return
        now = self.now()
        if self._started is None:
            self._started = now
        if now - self._started > self.params.max_time:
            self._finish(f"exploration stopped: max_time {self.params.max_time:.0f} s reached", EXIT_TIMEOUT)
            return
        if now - self._last_progress >= self.params.progress_period:
            self.progress("exploring")
        if self._spin != "done":
            self._first_turn(now)
            return
        if self._goal is not None:
            if self._handle is not None and now - self._goal_started > self.params.goal_timeout:
                goal = self._goal
                self.get_logger().warning(f"goal ({goal.x:.2f}, {goal.y:.2f}) timed out; canceling")
                self._handle.cancel_goal_async()
                self._end_goal(reached=False)
            return
        if self.map[2] < self._ended_at and now - self._ended_at < self.params.map_wait:
            return  # the map does not show what the robot saw at its last goal yet
        try:
            pose = self.frames.robot_pose(self.params.global_frame)
            result = self.explorer.next_goal(self.map[0], self.map[1], pose)
        except (FrameError, ValueError) as error:
            self.get_logger().warning(f"cannot choose a goal yet: {error}", throttle_duration_sec=5.0)
            return
        if result.status is ExplorationStatus.NO_FREE_SPACE:
            self.get_logger().info(
                f"no frontier yet: nothing within {self.explorer.params.robot_radius:.2f} m of the robot "
                f"({pose.x:.2f}, {pose.y:.2f}) is mapped free", throttle_duration_sec=5.0)
            return
        if result.status is ExplorationStatus.COMPLETE or result.goal is None:
            self._finish("exploration complete", 0)
            return
        self._send(result.goal)

    def _first_turn(self, now: float) -> None:
        if self._spin == "running":
            if now - self._goal_started > SPIN_ALLOWANCE + SPIN_WAIT:
                self.get_logger().warning("the first turn never finished; exploring without it")
                self._spin, self._ended_at = "done", now
            return
        if not self._spin_client.server_is_ready():
            if now - (self._started or now) > SPIN_WAIT:
                self.get_logger().warning(f"no '{SPIN_ACTION}' server; exploring without a first turn")
                self._spin = "done"
            return
        self._spin, self._goal_started = "running", now
        self.progress("turning once to see around")
        goal = Spin.Goal(target_yaw=2.0 * math.pi, time_allowance=duration_msg(SPIN_ALLOWANCE))
        self._spin_client.send_goal_async(goal).add_done_callback(self._on_spin_accepted)

    def _on_spin_accepted(self, future: Any) -> None:
        handle = future.result()
        if handle is None or not handle.accepted:
            self._spin_done(None)
            return
        handle.get_result_async().add_done_callback(self._spin_done)

    def _spin_done(self, future: Any) -> None:
        self._spin, self._ended_at = "done", self.now()

    def _send(self, goal: Pose2D) -> None:
        if not self._client.server_is_ready():
            self.get_logger().info(f"waiting for the {NAVIGATE_ACTION} action server",
                                   throttle_duration_sec=5.0)
            return
        self._goal, self._handle, self._goal_started = goal, None, self.now()
        self.goals += 1
        self.progress(f"goal {self.goals} -> ({goal.x:.2f}, {goal.y:.2f})")
        request = NavigateToPose.Goal()
        stamp = self.get_clock().now().to_msg()
        request.pose = pose_stamped(goal.x, goal.y, goal.yaw, self.params.global_frame, stamp)
        self._client.send_goal_async(request).add_done_callback(lambda f, g=goal: self._on_accepted(f, g))

    def _on_accepted(self, future: Any, goal: Pose2D) -> None:
        if goal is not self._goal:
            return  # a timed-out goal answered late
        handle = future.result()
        if handle is None or not handle.accepted:
            self.get_logger().warning("goal rejected")
            self._end_goal(reached=False)
            return
        self._handle = handle
        handle.get_result_async().add_done_callback(lambda f, g=goal: self._on_result(f, g))

    def _on_result(self, future: Any, goal: Pose2D) -> None:
        if goal is not self._goal:
            return
        self._result(future.result())

    def _result(self, response: Any) -> None:
        reached = response is not None and response.status == GoalStatus.STATUS_SUCCEEDED
        if not reached and response is not None:
            result = response.result
            self.get_logger().warning(f"goal failed (status {response.status}, error {result.error_code}: "
                                      f"{result.error_msg})")
        self._end_goal(reached)

    def _end_goal(self, reached: bool) -> None:
        assert self._goal is not None
        if reached:
            self.explorer.mark_reached(self._goal)
            self.reached += 1
        else:
            self.explorer.mark_failed(self._goal)
            self.failed += 1
        self._goal, self._handle, self._ended_at = None, None, self.now()

    def _finish(self, reason: str, code: int) -> None:
        if self._handle is not None:
            self._handle.cancel_goal_async()
        self.summary = self.progress(reason)
        self._ending, self.exit_code = True, code
        self._timer.cancel()
        if self.map_file:
            self.save(self.map_file, self._saved)
        else:
            self.finished = True

    def _saved(self, saved: bool) -> None:
        if not saved:
            print("explore: no map to save", file=sys.stderr, flush=True)
            self.exit_code = self.exit_code or 1
        self.finished = True

    # -- saving --------------------------------------------------------------------------------
    def save(self, name: str, done: Callable[[bool], None]) -> None:
        """Save the latest map as ``name``.pgm/.yaml: through the map_saver service if one appears
        within SAVER_DISCOVERY and answers within SAVER_ANSWER, else with map_io. ``done(saved)`` is
        called once, from a callback. A steady timer drives it (a stopped simulation cannot hold it)
        and nothing waits: the executor keeps serving meanwhile."""
        client = self.create_client(SaveMap, MAP_SAVER_SERVICE)
        started = time.monotonic()
        asked: list[Any] = []  # [future, monotonic s] once the request is out
        ended: list[bool] = []

        def end(by_service: bool) -> None:
            if ended:
                return  # an answer after the timeout, or a timeout after the answer
            ended.append(True)
            self.destroy_timer(timer)
            self.destroy_client(client)
            if by_service:
                print(f"explore: map saved to {name}.yaml (map_saver)", flush=True)
            done(by_service or self._save_here(name))

        def on_answer(future: Any) -> None:
            end(bool(future.result() is not None and future.result().result))

        def poll() -> None:
            now = time.monotonic()
            if not asked and client.service_is_ready():
                request = SaveMap.Request(map_url=name, free_thresh=SAVE_FREE_THRESH)
                asked[:] = [client.call_async(request), now]
                asked[0].add_done_callback(on_answer)
            elif (not asked and now - started > SAVER_DISCOVERY) or (asked and now - asked[1] > SAVER_ANSWER):
                end(False)

        timer = self.create_timer(SAVER_POLL, poll, clock=steady_clock())
        poll()

    def _save_here(self, name: str) -> bool:
        if self.map is None:
            return False
        save_map(OccupancyMap(self.map[0], self.map[1]), Path(name), free_thresh=SAVE_FREE_THRESH,
                 overwrite=True)
        print(f"explore: map saved to {name}.yaml", flush=True)
        return True


def main(argv: list[str] | None = None) -> int:
    """``nav-explore [-f my_map] [--max-time S] [--executor events|single] [--ros-args ...]``;
    exit 0 complete, 3 max time, 1 map not saved, 130 interrupted."""
    from rclpy.parameter import Parameter

    from ros_tools.runtime.executor import add_executor_argument
    from ros_tools.runtime.runner import run_nodes

    args_in = list(sys.argv[1:] if argv is None else argv)
    split = args_in.index("--ros-args") if "--ros-args" in args_in else len(args_in)
    parser = argparse.ArgumentParser(prog="nav-explore", description=__doc__.split("\n")[0])
    parser.add_argument("-f", dest="map_file", help="save the final map as MAP_FILE.pgm/.yaml")
    parser.add_argument("--max-time", type=float, help="stop after this many sim seconds")
    parser.add_argument("--no-sim-time", action="store_true", help="use the wall clock instead of /clock")
    add_executor_argument(parser)
    args = parser.parse_args(args_in[:split])
    overrides = [Parameter("use_sim_time", value=not args.no_sim_time)]
    if args.max_time is not None:
        overrides.append(Parameter("max_time", value=float(args.max_time)))
    # The run ends by itself: the node says when it finished (its map saved) and with which code.
    return run_nodes(lambda: [ExploreNode(args.map_file, parameter_overrides=overrides)], role="explore",
                     rclpy_args=["nav-explore", *args_in[split:]], executor=args.executor,
                     finished=lambda nodes: nodes[0].exit_code if nodes[0].finished else None,
                     interrupted_code=130)


if __name__ == "__main__":
    sys.exit(main())
