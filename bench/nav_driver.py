"""The client node of the whole-stack benchmarks: plans, navigates, counts collisions, reads /clock.

Used by bench_navigation and bench_soak through bench.nav_session. It also keeps the robot's ground
truth pose (sim2d's ``ground_truth``) and the battery's charge (``/battery_state``).
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

HOLD_GRACE = 3.0  # s (wall) the simulator may wait for a goal's acknowledgement (under its 5 s timeout)
GOAL_TIMEOUT = 120.0  # s (wall) per goal; a goal ideally takes under 40 s
PLAN_ACK_RETRY = 5.0  # s (wall) before an unacknowledged plan request is sent again
PLAN_SENDS = 6


@dataclass(frozen=True)
class GoalOutcome:
    """How one NavigateToPose goal ended.

    ``code`` is the result's error_code, None when no result came (not accepted, or no result within
    GOAL_TIMEOUT); ``message`` is the result's error_msg, or what this client saw instead.
    """

    ok: bool
    sim_s: float
    code: int | None
    message: str

    @property
    def explained(self) -> bool:
        """A failure the navigator explained: a result with a non-zero error code and a message."""
        return not self.ok and self.code is not None and self.code != 0 and bool(self.message.strip())


class Driver:
    """Client node: plans, navigates, counts collisions, reads /clock.

    Args:
        lockstep: join the simulator's lockstep so a goal request's DDS latency is not sim time.
        name: the node's name and lockstep role; also prefixes this client's warnings.
    """

    def __init__(self, lockstep: bool, name: str = "bench_navigation") -> None:
        import rclpy
        from nav2_msgs.action import ComputePathToPose, NavigateToPose
        from nav_msgs.msg import Odometry
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import BatteryState
        from std_msgs.msg import UInt32

        from ros_tools.runtime.actions import ActionClient  # safe to send from this thread while spun
        from ros_tools.runtime.executor import make_executor
        from ros_tools.runtime.lockstep import LockstepParticipant

        rclpy.init()
        self.name = name
        self.node = rclpy.create_node(name)
        self.nav = ActionClient(self.node, NavigateToPose, "navigate_to_pose")
        self.plan = ActionClient(self.node, ComputePathToPose, "compute_path_to_pose")
        self.collisions = 0
        self.sim_time = 0.0
        self.truth: tuple[float, float] | None = None
        self.battery: float | None = None  # charge, 0..1 (last /battery_state percentage)
        self.recoveries = 0
        self.wall_s = 0.0
        self.navigation_time = 0.0  # s, the navigator's own clock (last feedback's navigation_time)
        self.lost_requests = 0  # plan requests never acknowledged or never answered
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.node.create_subscription(UInt32, "sim2d/collision_count", self._on_collisions, latched)
        self.node.create_subscription(Clock, "/clock", self._on_clock, 10)
        self.node.create_subscription(Odometry, "ground_truth", self._on_truth, 10)
        self.node.create_subscription(BatteryState, "battery_state", self._on_battery, 10)
        # SingleThreadedExecutor: the EventsExecutor spun in this background thread never delivered
        # /clock or discovered the servers here (a busy core, then "not available" after 60 s; seen
        # 2026-11-26, cause not found). The result's done callback reads self.sim_time.
        # In lockstep the simulator waits for this client while a goal request is on its way, so
        # that DDS latency (wall ms, tenths of a sim second at rtf 10) is not navigation time.
        self.lockstep = LockstepParticipant(self.node, name) if lockstep else None
        self.executor = make_executor("single")
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self.executor.spin, daemon=True)
        self._thread.start()

    def _on_collisions(self, msg: Any) -> None:
        self.collisions = int(msg.data)

    def _on_truth(self, msg: Any) -> None:
        self.truth = (msg.pose.pose.position.x, msg.pose.pose.position.y)

    def _on_clock(self, msg: Any) -> None:
        self.sim_time = msg.clock.sec + msg.clock.nanosec * 1e-9

    def _on_battery(self, msg: Any) -> None:
        self.battery = float(msg.percentage)

    def servers_ready(self) -> bool:
        """Both action servers are discovered and /clock runs."""
        return bool(self.nav.server_is_ready() and self.plan.server_is_ready() and self.sim_time > 0.0)

    @staticmethod
    def _wait(future: Any, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not future.done():
            if time.monotonic() > deadline:
                return False
            time.sleep(0.02)
        return True

    @staticmethod
    def pose(x: float, y: float, yaw: float = 0.0) -> Any:
        from geometry_msgs.msg import PoseStamped

        msg = PoseStamped()
        msg.header.frame_id = "map"
        msg.pose.position.x, msg.pose.position.y = float(x), float(y)
        msg.pose.orientation.z, msg.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        return msg

    def path_length(self, start: tuple[float, float], goal: tuple[float, float]) -> float | None:
        """Length (m) of the planner's path from ``start`` to ``goal``; None when it fails."""
        from nav2_msgs.action import ComputePathToPose

        request = ComputePathToPose.Goal(goal=self.pose(*goal), start=self.pose(*start), use_start=True)
        for _ in range(PLAN_SENDS):
            sent = self.plan.send_goal_async(request)
            if self._wait(sent, PLAN_ACK_RETRY):
                break
            # A dropped goal request (the stack's known lost-request problem, see
            # nav_stack/ros/tools/goal_cli.py send_until_acknowledged): counted and shown, then sent again so
            # the simulator does not run for 30 wall s (minutes of sim time at max) while this client waits.
            self.lost_requests += 1
            print(f"{self.name}: compute_path_to_pose did not acknowledge a plan request within "
                  f"{PLAN_ACK_RETRY:.0f} s (wall); sending it again", flush=True)
        else:
            return None
        if not sent.result().accepted:
            return None
        result = sent.result().get_result_async()
        if not self._wait(result, 30.0):
            self.lost_requests += 1
            print(f"{self.name}: compute_path_to_pose accepted a plan request but sent no result "
                  "within 30 s (wall)", flush=True)
            return None
        if result.result().result.error_code != 0:
            return None
        poses = result.result().result.path.poses
        xy = np.array([(p.pose.position.x, p.pose.position.y) for p in poses])
        return float(np.hypot(*np.diff(xy, axis=0).T).sum()) if len(xy) > 1 else 0.0

    def navigate(self, goal: tuple[float, float, float]) -> GoalOutcome:
        """Send ``goal`` (x m, y m, yaw rad in map) and wait for its result (GOAL_TIMEOUT wall s at most).

        ``self.recoveries`` then holds the goal's recovery count, ``self.wall_s`` its wall seconds
        and ``self.navigation_time`` the navigator's own time of its last feedback.
        """
        from action_msgs.msg import GoalStatus
        from nav2_msgs.action import NavigateToPose

        started = self.sim_time
        self.recoveries = 0
        wall_started = time.monotonic()
        self.wall_s = 0.0

        self.navigation_time = 0.0

        def on_feedback(message: Any) -> None:
            self.recoveries = int(message.feedback.number_of_recoveries)
            elapsed = message.feedback.navigation_time
            self.navigation_time = elapsed.sec + elapsed.nanosec * 1e-9

        # The result is asked for and its sim time read in the executor thread the moment the goal is
        # accepted and the result arrives: polling from this thread would add its poll period.
        outcome: list[Any] = []
        ended: list[float] = []

        def on_result(future: Any) -> None:
            ended.append(self.sim_time)

        def on_accepted(future: Any) -> None:
            handle = future.result()
            if handle is not None and handle.accepted:
                result = handle.get_result_async()
                result.add_done_callback(on_result)
                outcome.append(result)

        requests: list[Any] = []  # held from before the send, so no report slips in between
        if self.lockstep is not None:
            self.lockstep.hold(lambda: bool(requests) and requests[0].done(), HOLD_GRACE)
        sent = self.nav.send_goal_async(NavigateToPose.Goal(pose=self.pose(*goal)),
                                        feedback_callback=on_feedback)
        requests.append(sent)
        sent.add_done_callback(on_accepted)
        if not self._wait(sent, 30.0) or not sent.result().accepted:
            return GoalOutcome(False, 0.0, None, "goal not accepted")
        deadline = time.monotonic() + GOAL_TIMEOUT
        while not ended and time.monotonic() < deadline:
            time.sleep(0.02)
        self.wall_s = time.monotonic() - wall_started
        if not ended:
            sent.result().cancel_goal_async()
            return GoalOutcome(False, self.sim_time - started, None, "timeout")
        response = outcome[0].result()
        ok = response.status == GoalStatus.STATUS_SUCCEEDED
        return GoalOutcome(ok, ended[0] - started, int(response.result.error_code), response.result.error_msg)

    def close(self) -> None:
        import rclpy

        self.executor.shutdown()  # first: destroying an entity wakes an executor spinning in another thread
        if self.lockstep is not None:
            self.lockstep.destroy()
        self.node.destroy_node()
        rclpy.try_shutdown()
