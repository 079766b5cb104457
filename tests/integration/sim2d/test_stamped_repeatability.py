"""Two lockstep drives with the same stamped commands give the same trajectory, to the last bit.

Issue 17: in lockstep the simulator may be up to ``lockstep.max_lead`` ahead of the controller, so a
command applied when it arrives takes effect at a sim time set by wall timing, and two runs of the
same mission part ways. sim2d now applies a TwistStamped command at stamp +
``stamped_cmd_vel_delay`` (sim2d/core/command_schedule.py) and publishes /clock after the data of
the same time. Here a closed-loop driver (a sim-time timer; its command depends on the odometry
stamped at or before its cycle, so a command applied at a different time changes all that follow)
drives sim2d at full speed twice, each time in a fresh simulator process, and the ground truth of
the two drives must be identical at every stamp. Each command leaves after a random wall delay (the
driver holds the simulator meanwhile), so the two runs' wall timings surely differ: applied on
arrival, as before, the drives part within the first second.
"""

from __future__ import annotations

import math
import random
import threading
import time
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

from geometry_msgs.msg import TwistStamped
from nav_msgs.msg import Odometry
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from navsuite_testing.ros import BackgroundSpin, connected, start_python, stop_process, wait_until
from ros_tools.runtime.lockstep import LockstepParticipant

pytestmark = pytest.mark.ros

ROLE = "repeat_driver"
DRIVE_S = 4.0          # s of sim time each drive lasts
PERIOD_S = 0.05        # s: the driver's control period (controller_server's 20 Hz)
TARGET = (0.0, 0.3)    # m, map = odom at the spawn below: where the driver steers to
JITTER_S = 0.02        # wall s: a command goes out up to this long after its cycle (a loaded machine)


def _sim() -> Any:
    return start_python("sim2d.ros.cli", [
        "--world", "turtlebot3_world", "--robot", "waffle", "--rtf", "max", "--stamped",
        "--x", "-2.0", "--y", "-0.5", "--yaw", "0.0", "--lockstep-participants", ROLE])


class Driver(Node):
    """Steers toward TARGET from the odometry stamped at or before each cycle; records ground truth."""

    def __init__(self, context: Any) -> None:
        super().__init__("repeat_driver", context=context,
                         parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.truth: dict[int, tuple[float, ...]] = {}
        self.odom: list[tuple[int, float, float, float]] = []   # (stamp ns, x, y, yaw)
        self.pub = self.create_publisher(TwistStamped, "/cmd_vel", 10)
        subs = [self.create_subscription(Odometry, "/odom", self._on_odom, 100),
                self.create_subscription(Odometry, "/ground_truth", self._on_truth, 100)]
        self.timer = self.create_timer(PERIOD_S, self._cycle)
        self.lockstep = LockstepParticipant(self, ROLE, ready=connected([self.pub, *subs]))
        self._jitter = random.Random()   # unseeded on purpose: each run's wall timing differs
        self._outbox: list[tuple[float, TwistStamped, threading.Event]] = []   # (wall due, msg, sent)
        self.create_timer(0.001, self._send_due, clock=Clock(clock_type=ClockType.STEADY_TIME))

    @staticmethod
    def _pose(msg: Odometry) -> tuple[int, float, float, float]:
        p, q = msg.pose.pose, msg.pose.pose.orientation
        stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
        return stamp, p.position.x, p.position.y, 2.0 * math.atan2(q.z, q.w)

    def _on_odom(self, msg: Odometry) -> None:
        self.odom.append(self._pose(msg))

    def _on_truth(self, msg: Odometry) -> None:
        stamp, x, y, yaw = self._pose(msg)
        self.truth[stamp] = (x, y, yaw, msg.twist.twist.linear.x, msg.twist.twist.angular.z)

    def _cycle(self) -> None:
        now = self.get_clock().now().nanoseconds
        cycle = now + self.timer.time_until_next_call() - self.timer.timer_period_ns
        known = [o for o in self.odom if o[0] <= cycle]
        if cycle <= 0 or not known:
            return
        _, x, y, yaw = known[-1]
        heading = math.atan2(TARGET[1] - y, TARGET[0] - x)
        msg = TwistStamped()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(cycle, 1_000_000_000)
        msg.twist.linear.x = 0.22
        msg.twist.angular.z = max(-1.0, min(1.0, 2.5 * math.remainder(heading - yaw, math.tau)))
        self._publish_later(msg)

    def _publish_later(self, msg: TwistStamped) -> None:
        """Publish at once or after a random wall delay, holding the simulator meanwhile (as a
        controller whose work is offloaded does): the command reaches the sim somewhere inside its
        lead window, and where depends on wall timing, which a command applied on arrival feels."""
        delay = self._jitter.uniform(-JITTER_S, JITTER_S)
        if delay <= 0.0:     # half of them at once
            self.pub.publish(msg)
            return
        sent = threading.Event()
        self.lockstep.hold(sent.is_set, 2.0)
        self._outbox.append((time.monotonic() + delay, msg, sent))

    def _send_due(self) -> None:
        now = time.monotonic()
        while self._outbox and self._outbox[0][0] <= now:
            _, msg, sent = self._outbox.pop(0)
            self.pub.publish(msg)
            sent.set()


def _drive(context: Any) -> dict[int, tuple[float, ...]]:
    sim = _sim()
    driver = Driver(context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(driver)
    spin = BackgroundSpin(executor, "driver")
    try:
        wait_until(lambda: max(driver.truth, default=0) >= DRIVE_S * 1e9, 60.0, "the drive's end")
    finally:
        spin.stop()  # first: nothing may be destroyed under a spinning thread
        driver.lockstep.destroy()
        driver.destroy_node()
        out = stop_process(sim)
    assert "stamped cmd_vel arrived after" not in out, out[-2000:]
    return driver.truth


def test_two_drives_agree_exactly(ros_context: Any) -> None:
    first, second = _drive(ros_context), _drive(ros_context)
    common = sorted(t for t in set(first) & set(second) if t <= DRIVE_S * 1e9)
    recorded = sum(1 for t in first if t <= DRIVE_S * 1e9)
    assert len(common) >= 0.9 * recorded > 50, f"{len(common)} of {recorded} ground-truth stamps in common"
    moved = math.hypot(first[common[-1]][0] - first[common[0]][0], first[common[-1]][1] - first[common[0]][1])
    assert moved > 0.3, f"the robot moved only {moved:.2f} m"
    for stamp in common:
        diff = max(abs(a - b) for a, b in zip(first[stamp], second[stamp], strict=True))
        assert diff <= 1e-9, f"the drives part at sim {stamp * 1e-9:.3f} s: {first[stamp]} vs {second[stamp]}"
