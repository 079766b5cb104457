"""``CbPureSpinning(yaw, max_w)``: turn in place by ``yaw`` rad commanding /cmd_vel directly.

As SMACC2's: a 10 Hz loop (machine clock, so sim time) accumulates the yaw turned from CpPose and
commands ω = clamp(k_p · remaining, ±max_w) until the remaining angle is below ``yaw_tolerance``
(0.1 rad). Fixed here: the loop always ends with a zero twist (SMACC2 leaves the last command on),
stops as soon as the state exits (``is_shutdown_requested``), and posts EvCbFailure when it did not
finish within ``timeout_s`` (default 2·|yaw|/max_w + 10 s) instead of spinning forever.
"""

from __future__ import annotations

import math

from smacc_py.clients.cl_nav2z.client import ClNav2Z
from smacc_py.clients.cl_nav2z.cp_pose import CpPose
from smacc_py.clients.cl_nav2z.geometry import normalize_angle
from smacc_py.core import SmaccAsyncClientBehavior
from smacc_py.ros.timing import sleep_on_machine_clock

CONTROL_PERIOD_S = 0.1  # 10 Hz, as SMACC2


class CbPureSpinning(SmaccAsyncClientBehavior):
    """Spin ``yaw`` rad (sign = direction) at most ``max_w`` rad/s."""

    def __init__(
        self,
        yaw: float,
        max_w: float = 0.5,
        *,
        k_p: float = 1.0,
        yaw_tolerance: float = 0.1,
        timeout_s: float | None = None,
    ) -> None:
        if not max_w > 0.0 or not k_p > 0.0 or not yaw_tolerance > 0.0:
            raise ValueError(
                f"CbPureSpinning: max_w, k_p and yaw_tolerance must be > 0, got {max_w}, {k_p}, "
                f"{yaw_tolerance}"
            )
        self.yaw, self.max_w, self.k_p, self.yaw_tolerance = float(yaw), float(max_w), k_p, yaw_tolerance
        self.timeout_s = timeout_s if timeout_s is not None else 2.0 * abs(yaw) / max_w + 10.0
        self.traveled = 0.0

    def on_entry(self) -> None:
        client = self.requires_client(ClNav2Z)
        cp_pose = self.requires_component(CpPose)
        start = self.sm.now()
        last = cp_pose.refresh()
        outcome: str | None = None
        try:
            while outcome is None:
                if self.sm.now() - start > self.timeout_s:
                    outcome = "timeout"
                    break
                pose = cp_pose.refresh()
                if pose is not None:
                    if last is not None:
                        self.traveled += normalize_angle(pose[2] - last[2])
                    last = pose
                    remaining = self.yaw - self.traveled
                    if abs(remaining) < self.yaw_tolerance:
                        outcome = "success"
                        break
                    client.publish_twist(0.0, max(-self.max_w, min(self.max_w, self.k_p * remaining)))
                if not sleep_on_machine_clock(self, CONTROL_PERIOD_S):
                    return  # the state is exiting: finally stops the robot
        finally:
            client.publish_twist()
        if outcome == "success":
            self.post_success_event(traveled=self.traveled)
        else:
            self.post_failure_event(
                traveled=self.traveled,
                reason=f"CbPureSpinning timed out after {self.timeout_s:.1f} s having turned "
                f"{math.degrees(self.traveled):.0f} of {math.degrees(self.yaw):.0f} deg",
            )
