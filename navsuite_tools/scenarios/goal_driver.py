"""Send a list of NavigateToPose goals one after the other: the goal-list mission of the scenario farm.

One process for the whole list, a lockstep participant (role ``scenario_goals``) that reports once
the ``navigate_to_pose`` server is ready; the farm names the role in nav-bringup's ``--participant``
list, so the simulator waits for it and sim time only passes while a goal is being driven (a process
per goal would let the simulator run on between them, and the mission's sim time would measure
process start-ups). It stops at the first goal that does not succeed.

Lines (read by navsuite_tools.scenarios.outcome)::

    goal 1: result: SUCCEEDED (error_code 0) in 12.30 s sim
    goal 2: result: ABORTED (error_code 208): <error_msg> in 0.40 s sim
    goals: 1 of 2 reached; sim 12.70 s

Retry after a respawn (``--retries N``, default 2): when the navigation process dies under a goal
(navsuite_tools.scenarios.navigation_watch notices it), the goal ends as the navigator would end it,
``goal 1: result: ABORTED (error_code 9000): the navigation process <role>:<pid> died ...`` (Nav2's
UNKNOWN, bt_navigator's code for a fault of its own), and once nav-bringup's respawned stack is active
and AMCL has its pose again the same goal is sent again (``goal 1: retry 1 of 2 ...``). Nav2 leaves
retries to the mission layer; this is that layer for a goal list. An ordinary abort is not retried.

With ``--goal-time S`` a goal still running S s of sim time after it was accepted is canceled
(``goal 1: not done after S s sim: canceling``, then its CANCELED result): a mission whose robot is
held on purpose (a Stop zone of the collision monitor) ends on sim time, not at the farm's wall-clock
deadline.

Exit status 0 when every goal succeeded, 1 otherwise (2 on bad arguments).
Usage: ``python -m navsuite_tools.scenarios.goal_driver '[[x, y, yaw], ...]' [--wait-for TOPIC]
[--goal-time S] [--retries N]`` (map frame; m, m, rad; S in sim s).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import time
from collections.abc import Sequence
from typing import Any

from ros_tools.geometry import set_yaw

ROLE = "scenario_goals"
WAIT_FOR_LIMIT = 20.0  # wall s the driver waits for a subscriber of its --wait-for topic
ACK_SENDS = 10  # copies of a goal sent (1 s apart, steady clock) before the driver gives up
STATUS_NAMES = {4: "SUCCEEDED", 5: "CANCELED", 6: "ABORTED"}  # action_msgs/GoalStatus
ABORTED = 6
#: the error code of a goal whose navigator died: Nav2's UNKNOWN, bt_navigator's for its own faults
NAVIGATOR_LOST = 9000
RETRIES = 2  # times a goal is sent again after the navigation process died under it
RESPAWN_LIMIT = 120.0  # wall s the driver waits for a respawned navigation stack
WATCH_PERIOD = 0.2  # wall s between two checks of the navigation process


def build_node(goals: list[tuple[float, float, float]], exit_code: list[int],
               wait_for: str | None = None, goal_time: float | None = None, retries: int = RETRIES) -> Any:
    """The driver node; ``exit_code[0]`` is set when the list is done, then the process stops itself.
    With ``wait_for`` (a topic) it is ready only once that topic has a subscriber too (or after
    WAIT_FOR_LIMIT wall s): a recorder that has not yet subscribed would miss the mission's start."""
    from geometry_msgs.msg import PoseStamped
    from nav2_msgs.action import NavigateToPose
    from rclpy.node import Node
    from rclpy.task import Future

    from navsuite_tools.scenarios.navigation_watch import NavigationWatch
    from ros_tools.runtime.actions import ActionClient, acknowledged
    from ros_tools.runtime.coroutines import spawn, until
    from ros_tools.runtime.waiting import first_of, sleep, steady_clock

    node = Node("scenario_goals")
    client = ActionClient(node, NavigateToPose, "navigate_to_pose")
    watch = NavigationWatch(node)

    def now_s() -> float:
        return float(node.get_clock().now().nanoseconds) * 1e-9

    async def drive() -> int:
        started, reached = now_s(), 0
        for index, (x, y, yaw) in enumerate(goals, 1):
            pose = PoseStamped()
            pose.header.frame_id = "map"
            pose.pose.position.x, pose.pose.position.y = x, y
            set_yaw(pose.pose.orientation, yaw)
            for attempt in range(retries + 1):
                status, lost = await send(index, NavigateToPose.Goal(pose=pose))
                if lost is None or attempt == retries or not await respawned(lost):
                    break
                print(f"goal {index}: retry {attempt + 1} of {retries}: the navigation stack is back",
                      flush=True)
            if status != 4:
                break
            reached += 1
        print(f"goals: {reached} of {len(goals)} reached; sim {now_s() - started:.2f} s", flush=True)
        return 0 if reached == len(goals) else 1

    async def send(index: int, goal: Any) -> tuple[int, int | None]:
        """Send one goal and print its result line; (status, pid of a navigation process that died
        under it, else None)."""
        goal_start = now_s()
        sent = await acknowledged(node, client, goal, ACK_SENDS)
        if sent is None or not sent.result().accepted:
            print(f"goal {index}: result: REJECTED (error_code 0): not accepted in 0.00 s sim", flush=True)
            return 0, None
        limit = _cancel_after(node, sent.result(), index, goal_time) if goal_time else None
        lost = Future()
        check = node.create_timer(WATCH_PERIOD, lambda: lost.done() or watch.dead() is None
                                  or lost.set_result(watch.dead()), clock=steady_clock())
        result_future = sent.result().get_result_async()
        first = await until(first_of(result_future, lost))
        node.destroy_timer(check)
        if limit is not None:
            node.destroy_timer(limit)
        if first is lost:
            pid = lost.result()
            print(f"goal {index}: result: ABORTED (error_code {NAVIGATOR_LOST}): the navigation process "
                  f"(pid {pid}) died while the goal was running in {now_s() - goal_start:.2f} s sim",
                  flush=True)
            return ABORTED, pid
        answer = result_future.result()
        status, result = answer.status, answer.result
        why = f": {result.error_msg}" if result.error_msg else ""
        print(f"goal {index}: result: {STATUS_NAMES.get(status, f'status {status}')} "
              f"(error_code {result.error_code}){why} in {now_s() - goal_start:.2f} s sim", flush=True)
        return status, None

    async def respawned(dead_pid: int) -> bool:
        """Wait (RESPAWN_LIMIT wall s; sim2d holds the world meanwhile) until the stack is back; whether
        it is."""
        deadline = time.monotonic() + RESPAWN_LIMIT
        print(f"goals: waiting for a respawned navigation stack (at most {RESPAWN_LIMIT:.0f} s wall)",
              flush=True)
        while not (watch.back(dead_pid) and client.server_is_ready()):
            if time.monotonic() > deadline:
                print(f"goals: the navigation stack did not come back within {RESPAWN_LIMIT:.0f} s",
                      flush=True)
                return False
            await sleep(node, WATCH_PERIOD, steady_clock())
        return True

    def start() -> None:
        if not client.server_is_ready() or now_s() <= 0.0:
            return
        timer.cancel()
        spawn(node, drive()).add_done_callback(finish)

    def finish(future: Any) -> None:
        exit_code[0] = future.result() if future.exception() is None else 1
        os.kill(os.getpid(), signal.SIGINT)  # the runner's orderly stop: leave lockstep, exit

    timer = node.create_timer(0.1, start, clock=steady_clock())
    give_up = time.monotonic() + WAIT_FOR_LIMIT

    def ready() -> bool:
        heard = wait_for is None or node.count_subscribers(wait_for) > 0 or time.monotonic() > give_up
        return bool(client.server_is_ready()) and heard

    node.scenario_ready = ready  # type: ignore[attr-defined]
    return node


def _cancel_after(node: Any, handle: Any, index: int, seconds: float) -> Any:
    """A one-shot timer on the node's (sim) clock that cancels the goal of ``handle`` after ``seconds``."""
    def expire() -> None:
        node.destroy_timer(timer)
        print(f"goal {index}: not done after {seconds:g} s sim: canceling", flush=True)
        handle.cancel_goal_async()

    timer = node.create_timer(seconds, expire)
    return timer


def parse_goals(text: str) -> list[tuple[float, float, float]]:
    """``[[x, y, yaw], ...]`` (yaw optional) → poses; ValueError naming the text otherwise."""
    goals = json.loads(text)
    if not isinstance(goals, list) or not goals:
        raise ValueError(f"expected a JSON list of [x, y, yaw], got {text!r}")
    poses = []
    for goal in goals:
        if not isinstance(goal, list) or len(goal) not in (2, 3):
            raise ValueError(f"expected [x, y, yaw], got {goal!r}")
        poses.append((float(goal[0]), float(goal[1]), float(goal[2]) if len(goal) == 3 else 0.0))
    return poses


def main(argv: Sequence[str] | None = None) -> int:
    import argparse

    from ros_tools.runtime.runner import run_nodes

    parser = argparse.ArgumentParser(prog="goal_driver", description=__doc__.splitlines()[0])
    parser.add_argument("goals", help="JSON list of [x, y, yaw] (map frame; m, m, rad)")
    parser.add_argument("--wait-for", help="a topic that must have a subscriber before the first goal")
    parser.add_argument("--goal-time", type=float, default=None,
                        help="sim s after which a running goal is canceled (default: never)")
    parser.add_argument("--retries", type=int, default=RETRIES,
                        help="times a goal is sent again after the navigation process died under it")
    args = parser.parse_args(argv)
    if args.retries < 0:
        parser.error(f"--retries must be >= 0, got {args.retries}")
    if args.goal_time is not None and not args.goal_time > 0.0:
        parser.error(f"--goal-time must be > 0 s, got {args.goal_time}")
    try:
        goals = parse_goals(args.goals)
    except ValueError as error:
        parser.error(str(error))
    exit_code = [1]
    nodes: list[Any] = []

    def build() -> list[Any]:
        nodes.append(build_node(goals, exit_code, args.wait_for, args.goal_time, args.retries))
        return nodes

    run_nodes(build, role=ROLE, rclpy_args=["--ros-args", "-p", "use_sim_time:=true"],
              ready=lambda: bool(nodes) and nodes[0].scenario_ready())
    return exit_code[0]


if __name__ == "__main__":
    sys.exit(main())
