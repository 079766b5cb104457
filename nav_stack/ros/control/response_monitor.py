"""The controller server's view of whether the robot obeys its commands (ROS side of
nav_stack/core/control/response.py): odometry age, the battery state, and the watchdog.

Why a class of its own: the controller server already steers, checks goals and serves an action;
knowing why a robot ignores it (empty battery, odometry stopped) is a separate concern with its own
subscription and its own failure (CONTROLLER_TIMED_OUT, see :class:`RobotUnresponsive`).
"""

from __future__ import annotations

from typing import Any

from sensor_msgs.msg import BatteryState

from nav_stack.core.control import Twist2D
from nav_stack.core.control.response import ResponseParams, ResponseWatchdog, diagnose, stillness_note
from nav_stack.ros.common.qos import DEFAULT

MIN_STALE_S = 0.5  # s: odometry older than max(timeout, this) counts as stopped (30 Hz is normal)


class ResponseMonitor:
    """Feed it every odometry message and every command; it raises RobotUnresponsive when due.

    Args:
        node: the controller server (its clock is the one ``now`` values come from).
        timeout: s (node clock) of significant commands without measured motion; 0 = off.
        battery_topic: sensor_msgs/BatteryState topic; "" = no battery known.
    """

    def __init__(self, node: Any, timeout: float, battery_topic: str) -> None:
        self.node = node
        self._watchdog = ResponseWatchdog(ResponseParams(timeout=timeout))
        self._stale_after = max(timeout, MIN_STALE_S)
        self._odom_at: float | None = None  # s (node clock) of the last odometry message
        self._battery_empty = False
        self.still_for = 0.0  # s the robot has been still under significant commands
        self._sub = node.create_subscription(BatteryState, battery_topic, self._on_battery,
                                             DEFAULT) if battery_topic else None

    def _on_battery(self, msg: BatteryState) -> None:
        self._battery_empty = (msg.percentage <= 0.0
                               or msg.power_supply_health == BatteryState.POWER_SUPPLY_HEALTH_DEAD)

    def odometry_received(self, now: float) -> None:
        self._odom_at = now

    def reset(self) -> None:
        """A new goal: forget the stillness of the last one."""
        self._watchdog.reset()
        self.still_for = 0.0

    def check(self, command: Twist2D, measured: Twist2D, now: float) -> None:
        """Record ``command`` (sent at ``now``) against ``measured`` (from odometry); raise
        RobotUnresponsive when the robot ignored its commands for the timeout and a cause is known."""
        odom_age = None if self._odom_at is None else now - self._odom_at
        if odom_age is None or odom_age >= self._stale_after:
            measured = Twist2D(0.0, 0.0)  # stopped odometry measures nothing
        self.still_for = self._watchdog.update(command, measured, now)
        if self._watchdog.unresponsive(self.still_for):
            error = diagnose(self.still_for, self._battery_empty, odom_age, self._stale_after)
            if error is not None:
                raise error

    def stillness_note(self) -> str:
        """Appended to a progress-checker failure (see core.control.response.stillness_note)."""
        return stillness_note(self.still_for)

    def destroy(self) -> None:
        if self._sub is not None:
            self.node.destroy_subscription(self._sub)
