"""A scripted stand-in for Nav2 + simulator as one real ROS node, for smacc_py integration tests.

``FakeNav2`` serves what sm_nav2_test_1 and the cl_nav2z behaviors talk to:

* action servers ``navigate_to_pose``, ``spin``, ``backup``, ``drive_on_heading``, ``follow_path``; each
  pops the next scripted outcome ("succeeded", "aborted" or "hold": run until cancelled) and records
  every goal and every cancel request; an empty script means "succeeded";
* bond heartbeats (bond/Status on /bond, 10 Hz) for ``bond_nodes``;
* an AMCL responder (unless ``amcl_echo`` is False): each /initialpose moves map→odom so the robot is
  there and answers on /amcl_pose (reliable, transient local);
* a world tick (100 Hz wall): /clock advancing ``clock_rate`` simulated seconds per wall second, the
  robot integrating /cmd_vel (unless ``frozen``), /odom and TF map→odom→base_link stamped in sim time. Every
  Twist received is kept in ``twists``;
* lockstep, as sim2d's (``lockstep_roles``, ``--lockstep ROLE``): the clock moves only while every
  named role's /lockstep/progress report is within one tick of it (sim2d.core.lockstep.LockstepGate),
  and stays put until each has reported once. Free-running at 10x on a loaded machine, the state
  machine read odometry late: CbPureSpinning turned 372 of 180 degrees (CI run 17).

One thread runs the fake: a SingleThreadedExecutor spun by ``start()``'s thread, with the goals'
execute callbacks as coroutines that wait for the next world tick (on this rclpy the EventsExecutor
re-polls a waiting coroutine without pause, half a core per goal, so the fake stays on the Python
executor). ``stop()`` ends spinning before it shuts the executor down and destroys the servers: a
Python executor shut down while its thread still runs a callback leaves an "exception was never
retrieved: cannot use Destroyable" at exit.

Navigation takes sim time, as a robot driving there would: a navigate_to_pose goal that is to succeed
ends after (distance / ``nav_speed``) s of sim time (at least one tick; cancelled meanwhile, it ends
CANCELED where it started), then teleports the robot to the goal, so TF agrees with what Nav2
reported. Instant success would let a fast client finish several legs between two readings of a
sensor that integrates the motion (the battery of autonomy_fake_stack.py).
"""

from __future__ import annotations

import contextlib
import math
import threading
import time
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from bond.msg import Status
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped, Twist
from nav2_msgs.action import BackUp, DriveOnHeading, FollowPath, NavigateToPose, Spin
from nav_msgs.msg import Odometry
from rclpy.action import ActionServer, CancelResponse
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header
from tf2_msgs.msg import TFMessage

from ros_tools.dds import keep_dds_local
from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC
from sim2d.core.lockstep import HOLD, LockstepGate

TICK_S = 0.01
#: wall s between re-sends of a held clock (sim2d's rate: a participant reports on each /clock)
RESEND_WALL_S = 0.1
#: wall s of silence after which a lockstep role no longer holds the clock (sim2d's lockstep.timeout)
LOCKSTEP_TIMEOUT_S = 10.0
START_S = 1000.0
NAV_SPEED = 1.0  # m/s of sim time a navigate_to_pose goal "drives" at
AMCL_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)
ACTIONS: dict[str, Any] = {
    "navigate_to_pose": NavigateToPose,
    "spin": Spin,
    "backup": BackUp,
    "drive_on_heading": DriveOnHeading,
    "follow_path": FollowPath,
}
ABORT_CODES = {
    "navigate_to_pose": 204,
    "spin": 701,
    "backup": 711,
    "drive_on_heading": 721,
    "follow_path": 105,
}


@dataclass
class ServerLog:
    """What one fake action server saw."""

    goals: list[Any] = field(default_factory=list)
    cancels: int = 0
    results: list[str] = field(default_factory=list)


def _tf(parent: str, child: str, x: float, y: float, yaw: float, stamp_s: float) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.header.stamp.sec = int(stamp_s)
    t.header.stamp.nanosec = int((stamp_s % 1.0) * 1e9)
    t.transform.translation.x, t.transform.translation.y = x, y
    t.transform.rotation.z, t.transform.rotation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return t


def _compose(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, float, float]:
    c, s = math.cos(a[2]), math.sin(a[2])
    return a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2]


def _inverse(a: tuple[float, float, float]) -> tuple[float, float, float]:
    c, s = math.cos(a[2]), math.sin(a[2])
    return -c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2]


class FakeNav2:
    """The fake stack; ``start()`` spins it in a background thread, ``stop()`` tears it down."""

    def __init__(
        self,
        context: Any,
        *,
        scripts: dict[str, Iterable[str]] | None = None,
        bond_nodes: Iterable[str] = ("planner_server", "controller_server", "bt_navigator"),
        clock_rate: float = 10.0,
        frozen: bool = False,
        amcl_echo: bool = True,
        nav_speed: float = NAV_SPEED,
        lockstep_roles: Iterable[str] = (),
    ) -> None:
        self.node = Node("fake_nav2", context=context)
        self.scripts = {name: deque(scripts.get(name, ()) if scripts else ()) for name in ACTIONS}
        self.logs = {name: ServerLog() for name in ACTIONS}
        self.bond_nodes = list(bond_nodes)
        self.clock_rate, self.frozen, self.amcl_echo = clock_rate, frozen, amcl_echo
        self.nav_speed = nav_speed
        self.sim_s = START_S
        self.odom_pose = (0.0, 0.0, 0.0)  # base_link in odom
        self.map_odom = (0.0, 0.0, 0.0)  # odom in map
        self.cmd = Twist()
        self.twists: list[Twist] = []
        self.initial_poses: list[tuple[float, float, float]] = []
        self._lock = threading.Lock()
        self._stopping = False
        self._tick_gate = Future()  # completed (and replaced) by every world tick
        roles = tuple(lockstep_roles)
        # a lead of one tick: the clock may move one step past the slowest role's report
        self._lockstep = LockstepGate(round(TICK_S * clock_rate * 1e9), LOCKSTEP_TIMEOUT_S, time.monotonic(),
                                      expected=roles, startup_timeout=LOCKSTEP_TIMEOUT_S) if roles else None
        self._last_send_wall = 0.0
        n = self.node
        self._servers = [
            ActionServer(n, action_type, name, self._executor_for(name),
                         cancel_callback=self._cancel_for(name))
            for name, action_type in ACTIONS.items()
        ]
        self._clock_pub = n.create_publisher(Clock, "/clock", 10)
        self._tf_pub = n.create_publisher(TFMessage, "/tf", 100)
        self._odom_pub = n.create_publisher(Odometry, "/odom", 10)
        self._bond_pub = n.create_publisher(Status, "/bond", 10)
        self._amcl_pub = n.create_publisher(PoseWithCovarianceStamped, "/amcl_pose", AMCL_QOS)
        n.create_subscription(Twist, "/cmd_vel", self._on_cmd_vel, 100)
        n.create_subscription(PoseWithCovarianceStamped, "/initialpose", self._on_initial_pose, 10)
        if self._lockstep is not None:
            n.create_subscription(Header, PROGRESS_TOPIC, self._on_progress, PROGRESS_QOS)
        n.create_timer(TICK_S, self._tick)
        n.create_timer(0.1, self._heartbeat)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(n)
        self._thread = threading.Thread(target=self._spin, daemon=True)

    # ------------------------------------------------------------------ lifecycle
    def start(self) -> FakeNav2:
        self._thread.start()
        return self

    def _spin(self) -> None:
        with contextlib.suppress(Exception):  # the context may shut down under us at teardown
            while not self._stopping and self.executor.context.ok():
                self.executor.spin_once(timeout_sec=0.1)

    def stop(self) -> None:
        self._stopping = True  # goals still running are never resumed
        self._thread.join(2.0)
        self.executor.shutdown()
        for server in self._servers:
            server.destroy()
        self.node.destroy_node()

    # ------------------------------------------------------------------ world
    def map_pose(self) -> tuple[float, float, float]:
        with self._lock:
            return _compose(self.map_odom, self.odom_pose)

    def teleport(self, x: float, y: float, yaw: float) -> None:
        """Put the robot at (x, y, yaw) in map (by moving it in odom)."""
        with self._lock:
            self.odom_pose = _compose(_inverse(self.map_odom), (x, y, yaw))

    def _on_progress(self, msg: Header) -> None:
        assert self._lockstep is not None
        stamp_ns = msg.stamp.sec * 1_000_000_000 + msg.stamp.nanosec
        self._lockstep.report(msg.frame_id, stamp_ns, time.monotonic())

    def _held(self, next_s: float) -> bool:
        """True while a lockstep role has not caught up with the clock (or has not reported yet)."""
        if self._lockstep is None:
            return False
        limit = self._lockstep.limit_ns(time.monotonic())
        # half a tick of slack: reports carry the clock's truncated ns, sim_s is a sum of float ticks
        slack_ns = TICK_S * self.clock_rate * 0.5e9
        return limit == HOLD or (limit is not None and next_s * 1e9 > limit + slack_ns)

    def _tick(self) -> None:
        dt = TICK_S * self.clock_rate
        if self._held(self.sim_s + dt):
            if time.monotonic() - self._last_send_wall >= RESEND_WALL_S:  # the time it holds at, again
                self._publish_clock(self.sim_s)
            return
        with self._lock:
            self.sim_s += dt
            if not self.frozen:
                x, y, yaw = self.odom_pose
                v, w = self.cmd.linear.x, self.cmd.angular.z
                self.odom_pose = (x + v * math.cos(yaw) * dt, y + v * math.sin(yaw) * dt, yaw + w * dt)
            stamp, odom, map_odom = self.sim_s, self.odom_pose, self.map_odom
        gate, self._tick_gate = self._tick_gate, Future()
        gate.set_result(stamp)
        self._publish_clock(stamp)
        odom_tf = _tf("odom", "base_link", *odom, stamp)
        self._tf_pub.publish(TFMessage(transforms=[_tf("map", "odom", *map_odom, stamp), odom_tf]))
        msg = Odometry()
        msg.header, msg.child_frame_id = odom_tf.header, "base_link"
        msg.pose.pose.position.x, msg.pose.pose.position.y = odom[0], odom[1]
        msg.pose.pose.orientation = odom_tf.transform.rotation
        self._odom_pub.publish(msg)

    def _publish_clock(self, stamp: float) -> None:
        clock = Clock()
        clock.clock.sec, clock.clock.nanosec = int(stamp), int((stamp % 1.0) * 1e9)
        self._clock_pub.publish(clock)
        self._last_send_wall = time.monotonic()

    def _heartbeat(self) -> None:
        for node_id in list(self.bond_nodes):
            self._bond_pub.publish(
                Status(
                    id=node_id, instance_id="fake", active=True, heartbeat_timeout=4.0, heartbeat_period=0.1
                )
            )

    def _on_cmd_vel(self, msg: Twist) -> None:
        with self._lock:
            self.cmd = msg
            self.twists.append(msg)

    def _on_initial_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        pose = (p.x, p.y, math.atan2(2 * q.w * q.z, 1 - 2 * q.z * q.z))
        with self._lock:
            self.initial_poses.append(pose)
            if not self.amcl_echo:
                return
            self.map_odom = _compose(pose, _inverse(self.odom_pose))
        self._amcl_pub.publish(msg)

    # ------------------------------------------------------------------ action servers
    async def _drive(self, goal_handle: Any) -> bool:
        """Wait (distance / nav_speed) s of sim time for a navigate_to_pose goal; False when cancelled."""
        target = goal_handle.request.pose.pose.position
        x, y, _ = self.map_pose()
        distance = math.hypot(target.x - x, target.y - y)
        until_s = self.sim_s + max(TICK_S * self.clock_rate, distance / self.nav_speed)
        while self.sim_s < until_s:
            if goal_handle.is_cancel_requested:
                return False
            await self._tick_gate
        return True

    def _cancel_for(self, name: str) -> Any:
        def cancel(goal_handle: Any) -> CancelResponse:
            with self._lock:
                self.logs[name].cancels += 1
            return CancelResponse.ACCEPT

        return cancel

    def _executor_for(self, name: str) -> Any:
        action_type = ACTIONS[name]

        async def execute(goal_handle: Any) -> Any:
            with self._lock:
                self.logs[name].goals.append(goal_handle.request)
                script = self.scripts[name]
                outcome = script.popleft() if script else "succeeded"
            result = action_type.Result()
            if outcome == "hold":
                while not goal_handle.is_cancel_requested:
                    await self._tick_gate
                outcome = "canceled"
            elif outcome == "succeeded" and name == "navigate_to_pose" and not await self._drive(goal_handle):
                outcome = "canceled"
            if outcome == "canceled":
                goal_handle.canceled()
            elif outcome == "aborted":
                result.error_code = ABORT_CODES[name]
                result.error_msg = f"fake {name} aborted as scripted"
                goal_handle.abort()
            else:
                if name == "navigate_to_pose":
                    pose = goal_handle.request.pose.pose
                    q = pose.orientation
                    self.teleport(
                        pose.position.x, pose.position.y, math.atan2(2 * q.w * q.z, 1 - 2 * q.z * q.z)
                    )
                goal_handle.succeed()
            self.logs[name].results.append(outcome)
            return result

        return execute


def main() -> int:
    """Run FakeNav2 as a process (stands in for ``nav-bringup`` in demo tests); prints "Nav2 is ready"."""
    import argparse

    keep_dds_local()
    import rclpy
    from rclpy.context import Context

    parser = argparse.ArgumentParser()
    parser.add_argument("--rtf", type=float, default=10.0)
    parser.add_argument("--abort-navigation", action="store_true")
    parser.add_argument("--lockstep", metavar="ROLE", action="append", default=[],
                        help="hold the clock for this lockstep role (repeatable), as sim2d does")
    options = parser.parse_args()
    context = Context()
    rclpy.init(context=context)
    scripts = {"navigate_to_pose": ["aborted"]} if options.abort_navigation else None
    fake = FakeNav2(context, scripts=scripts, clock_rate=options.rtf, lockstep_roles=options.lockstep).start()
    return serve_until_signalled(fake, context, "fake stack up; Nav2 is ready")


def serve_until_signalled(fake: FakeNav2, context: Any, ready_line: str) -> int:
    """Run a started fake as a stack process: print ``ready_line`` (what the launcher waits for), serve
    until SIGINT or SIGTERM, then stop the fake and shut its context down; exit status 0."""
    import signal

    import rclpy

    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    print(ready_line, flush=True)
    stop.wait()
    fake.stop()
    rclpy.shutdown(context=context)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
