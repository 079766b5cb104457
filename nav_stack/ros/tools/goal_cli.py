"""nav-goal: send goals to the running stack from the command line and watch them live.

    nav-goal initial-pose -2.0 -0.5 0.0
    nav-goal goto 0.0 2.0 [1.57] [--behavior-tree my_tree.xml] [--frame map]
    nav-goal waypoints config/waypoints_example.yaml      # a list of [x, y, yaw] (or {waypoints: [...]})
    nav-goal --namespace robot2 goto 1.0 0.5 0.0          # a fleet's robot (nav-bringup --robots N)

``--namespace`` puts the client in the robot's namespace, so its actions and topics are the robot's
(``/robot2/navigate_to_pose``, ``/robot2/initialpose``, ``/robot2/amcl_pose``), as a Nav2 client
started in that namespace (BasicNavigator(namespace=...)) sees them; /clock stays global.

While a goal runs one status line shows distance remaining, ETA, recoveries and elapsed time;
the end prints the result with its error code and message. Exit status: 0 on success, 1 on
failure (aborted, rejected, missed waypoints, unconfirmed initial pose), 2 on bad input, 130
after Ctrl-C or SIGTERM (which cancel the goal first).

The client spins its executor (``--executor events``, the default, or ``single``) from the main
thread until a future completes; its callbacks only record feedback and results. Ctrl-C and SIGTERM
only set a flag (the shared runner's, ros_tools.runtime.runner.ros_process) that the spin loop turns
into KeyboardInterrupt between two spins: raised from the signal handler
inside the C++ EventsExecutor, it could leave the executor hung and the goal never canceled.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from nav_stack.core.fleet_spec import FleetSpecError, check_robot_name
from ros_tools.dds import keep_dds_local

if TYPE_CHECKING:
    from ros_tools.runtime.runner import RosProcess

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130
SERVER_TIMEOUT = 30.0  # s (wall) to find the action server
CANCEL_TIMEOUT = 10.0  # s (wall) to wait for the result after a cancel
STATUS_PERIOD = 0.5  # s between status lines


def load_waypoints(path: Path) -> list[tuple[float, float, float]]:
    """[x, y, yaw] triples from a YAML list (or a ``waypoints:`` key); ValueError naming file and index."""
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise ValueError(f"{path}: cannot read waypoints: {error}") from error
    if isinstance(data, dict):
        data = data.get("waypoints")
    if not isinstance(data, list) or not data:
        raise ValueError(f"{path}: expected a non-empty list of [x, y, yaw] (or a 'waypoints:' key)")
    out = []
    for index, item in enumerate(data):
        if not isinstance(item, list | tuple) or len(item) not in (2, 3):
            raise ValueError(f"{path}: waypoint {index}: expected [x, y] or [x, y, yaw], got {item!r}")
        try:
            values = [float(v) for v in item]
        except (TypeError, ValueError):
            raise ValueError(f"{path}: waypoint {index}: {item!r} holds a non-number") from None
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"{path}: waypoint {index}: {item!r} is not finite")
        out.append((values[0], values[1], values[2] if len(values) == 3 else 0.0))
    return out


def _namespace(text: str) -> str:
    """``/robot2`` for ``robot2`` or ``/robot2/`` ("" for none); ArgumentTypeError for a name ROS refuses."""
    parts = [part for part in text.strip().split("/") if part]
    try:
        for part in parts:
            check_robot_name(part)
    except FleetSpecError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return "/" + "/".join(parts) if parts else ""


def _parser() -> argparse.ArgumentParser:
    from ros_tools.runtime.executor import add_executor_argument

    parser = argparse.ArgumentParser(prog="nav-goal", description="Send goals to the navigation stack.")
    add_executor_argument(parser)
    parser.add_argument("--namespace", default="", type=_namespace,
                        help="the robot's namespace in a fleet (robot2: /robot2/navigate_to_pose)")
    sub = parser.add_subparsers(dest="command", required=True)
    pose = sub.add_parser("initial-pose", help="set AMCL's pose and wait until it is confirmed")
    for name in ("x", "y", "yaw"):
        pose.add_argument(name, type=float)
    goto = sub.add_parser("goto", help="navigate_to_pose")
    goto.add_argument("x", type=float)
    goto.add_argument("y", type=float)
    goto.add_argument("yaw", type=float, nargs="?", default=0.0)
    goto.add_argument("--behavior-tree", default="", help="BT XML file (default: bt_navigator's)")
    goto.add_argument("--frame", default="map")
    waypoints = sub.add_parser("waypoints", help="follow_waypoints from a YAML file")
    waypoints.add_argument("file", type=Path)
    waypoints.add_argument("--frame", default="map")
    return parser


class GoalRunner:
    """One client node; sends a goal, prints progress, cancels on Ctrl-C or SIGTERM.

    ``process`` is the shared runner's (``ros_process``): rclpy set up without its own signal
    handler, and a stop flag that SIGINT and SIGTERM raise; ``spin_until`` turns it into
    KeyboardInterrupt between two spins.
    """

    def __init__(self, process: RosProcess, executor: str | None = None) -> None:
        import rclpy
        from rclpy.parameter import Parameter

        self._process = process
        self.node = rclpy.create_node("nav_goal", context=process.context,
                                      parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.executor = process.executor(executor)
        self.executor.add_node(self.node)
        self._last_status = 0.0

    def close(self) -> None:
        """Shut the executor down and destroy the node (the context is the process's to shut down)."""
        self.executor.shutdown()
        self.node.destroy_node()

    def spin_until(self, done: Any, timeout: float | None = None, interruptible: bool = True) -> bool:
        """Spin until ``done()`` (True) or ``timeout`` s of wall time (False); KeyboardInterrupt after
        Ctrl-C unless ``interruptible`` is False (the cancel that follows a Ctrl-C)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while not done():
            if interruptible and self._process.stop_requested:
                raise KeyboardInterrupt
            if deadline is not None and time.monotonic() > deadline:
                return False
            self.executor.spin_once(timeout_sec=0.05)
        return True

    def status(self, text: str) -> None:
        now = time.monotonic()
        if now - self._last_status >= STATUS_PERIOD:
            self._last_status = now
            print(f"\r{text:<100}", end="", flush=True)

    def _cancel_all(self, client: Any, action_type: Any, copies: list[tuple[Any, Any]]) -> None:
        """Cancel every copy of a goal the server may have accepted; wait (CANCEL_TIMEOUT s) for the
        results of the acknowledged ones and the cancel responses of the others.

        A copy still unacknowledged may have reached the server with its acknowledgement lost on the
        way back: it is canceled by its goal id (a server that never got it answers "unknown goal").
        """
        from rclpy.action.client import ClientGoalHandle

        self.spin_until(lambda: any(f.done() for f, _ in copies), CANCEL_TIMEOUT / 2, interruptible=False)
        handles, waits = [], []
        for future, goal_id in copies:
            if future.done():
                if future.result() is not None and future.result().accepted:
                    handles.append(future.result())
                    waits.append(future.result().get_result_async())
                continue
            assumed = action_type.Impl.SendGoalService.Response(accepted=True)
            handles.append(ClientGoalHandle(client, goal_id, assumed))
        waits += [handle.cancel_goal_async() for handle in handles]
        self.spin_until(lambda: all(w.done() for w in waits), CANCEL_TIMEOUT, interruptible=False)

    def run_action(self, action_type: Any, name: str, goal: Any, describe: Any) -> tuple[int, Any]:
        """Send ``goal`` to ``name``; (GoalStatus, result) or raise on no server/rejection."""
        from rclpy.action import ActionClient

        from ros_tools.runtime.actions import send_until_acknowledged

        client = ActionClient(self.node, action_type, name)
        if not self.spin_until(client.server_is_ready, SERVER_TIMEOUT):
            raise RuntimeError(f"no '{name}' action server after {SERVER_TIMEOUT:.0f} s "
                               "(is nav-bringup running?)")
        started = time.monotonic()
        copies: list[tuple[Any, Any]] = []  # (future, goal id) of every copy sent
        try:
            try:
                sent = send_until_acknowledged(
                    client, goal, SERVER_TIMEOUT, self.spin_until,
                    lambda msg: self.status(describe(msg.feedback, started)), copies)
            except TimeoutError as error:
                raise RuntimeError(str(error)) from None
            handle = sent.result()
            if not handle.accepted:
                raise RuntimeError(f"'{name}' rejected the goal")
            outcome = handle.get_result_async()
            self.spin_until(outcome.done)
        except KeyboardInterrupt:
            print("\nCtrl-C: canceling the goal...", flush=True)
            self._cancel_all(client, action_type, copies)
            raise
        print()
        response = outcome.result()
        return response.status, response.result


def _pose_stamped(x: float, y: float, yaw: float, frame: str) -> Any:
    from geometry_msgs.msg import PoseStamped

    pose = PoseStamped()
    pose.header.frame_id = frame
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
    return pose


def _status_name(status: int) -> str:
    from action_msgs.msg import GoalStatus

    names = {GoalStatus.STATUS_SUCCEEDED: "SUCCEEDED", GoalStatus.STATUS_ABORTED: "ABORTED",
             GoalStatus.STATUS_CANCELED: "CANCELED"}
    return names.get(status, f"status {status}")


def goto(runner: GoalRunner, args: argparse.Namespace) -> int:
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import NavigateToPose

    goal = NavigateToPose.Goal(pose=_pose_stamped(args.x, args.y, args.yaw, args.frame),
                               behavior_tree=args.behavior_tree)

    def describe(fb: Any, started: float) -> str:
        eta = fb.estimated_time_remaining.sec + fb.estimated_time_remaining.nanosec * 1e-9
        nav = fb.navigation_time.sec + fb.navigation_time.nanosec * 1e-9
        return (f"navigating: {fb.distance_remaining:5.2f} m left | ETA {eta:5.1f} s | "
                f"recoveries {fb.number_of_recoveries} | {nav:5.1f} s sim, "
                f"{time.monotonic() - started:5.1f} s wall")

    action = runner.node.resolve_topic_name("navigate_to_pose")   # /robot2/navigate_to_pose with --namespace
    print(f"{action} ({args.x:.2f}, {args.y:.2f}, {args.yaw:.2f}) in '{args.frame}'", flush=True)
    status, result = runner.run_action(NavigateToPose, "navigate_to_pose", goal, describe)
    print(f"result: {_status_name(status)} (error_code {result.error_code})"
          + (f": {result.error_msg}" if result.error_msg else ""))
    return EXIT_OK if status == GoalStatus.STATUS_SUCCEEDED else EXIT_FAILED


def waypoints(runner: GoalRunner, args: argparse.Namespace) -> int:
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import FollowWaypoints

    points = load_waypoints(args.file)
    goal = FollowWaypoints.Goal(poses=[_pose_stamped(x, y, yaw, args.frame) for x, y, yaw in points])

    def describe(fb: Any, started: float) -> str:
        elapsed = time.monotonic() - started
        return f"following waypoints: at {fb.current_waypoint + 1}/{len(points)} | {elapsed:5.1f} s"

    print(f"follow_waypoints: {len(points)} waypoints from {args.file}", flush=True)
    status, result = runner.run_action(FollowWaypoints, "follow_waypoints", goal, describe)
    missed = [f"#{m.index} (error {m.error_code})" for m in result.missed_waypoints]
    print(f"result: {_status_name(status)} (error_code {result.error_code})"
          + (f": {result.error_msg}" if result.error_msg else "")
          + (f"; missed: {', '.join(missed)}" if missed else ""))
    return EXIT_OK if status == GoalStatus.STATUS_SUCCEEDED and not missed else EXIT_FAILED


def initial_pose(runner: GoalRunner, args: argparse.Namespace) -> int:
    from rclpy.parameter import Parameter

    from nav_stack.ros.localization.initial_pose_publisher import InitialPosePublisher

    publisher = InitialPosePublisher(parameter_overrides=[
        Parameter("x", value=args.x), Parameter("y", value=args.y), Parameter("yaw", value=args.yaw),
        Parameter("use_sim_time", value=True)])
    runner.executor.add_node(publisher)
    try:
        runner.spin_until(lambda: publisher.done is not None)
    finally:
        runner.executor.remove_node(publisher)
        publisher.destroy_node()
    print("initial pose confirmed by AMCL" if publisher.done else "AMCL did not confirm the initial pose")
    return EXIT_OK if publisher.done else EXIT_FAILED


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry ``nav-goal``."""
    args = _parser().parse_args(sys.argv[1:] if argv is None else argv)
    if args.command == "waypoints":
        try:
            load_waypoints(args.file)
        except ValueError as error:
            print(f"nav-goal: error: {error}", file=sys.stderr)
            return EXIT_USAGE
    keep_dds_local()
    from ros_tools.runtime.runner import ros_process

    ros_args = ["--ros-args", "-r", f"__ns:={args.namespace}"] if args.namespace else []
    with ros_process(["nav_goal", *ros_args]) as process:
        runner = GoalRunner(process, args.executor)
        try:
            command = {"goto": goto, "waypoints": waypoints, "initial-pose": initial_pose}[args.command]
            return command(runner, args)
        except KeyboardInterrupt:
            return EXIT_INTERRUPTED
        except RuntimeError as error:
            print(f"nav-goal: error: {error}", file=sys.stderr)
            return EXIT_FAILED
        finally:
            runner.close()


if __name__ == "__main__":
    raise SystemExit(main())
