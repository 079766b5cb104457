"""``CbPureSpinning(yaw, max_w)``: turn in place by ``yaw`` rad commanding /cmd_vel directly.

As SMACC2's: a 10 Hz control loop (machine clock, so sim time) accumulates the yaw turned from CpPose
and commands ω = clamp(k_p · remaining, ±max_w) until the remaining angle is below ``yaw_tolerance``
(0.1 rad). Fixed here: the loop always ends with a zero twist (SMACC2 leaves the last command on),
stops as soon as the state exits, and posts EvCbFailure when it did not finish within ``timeout_s``
(default 2·|yaw|/max_w + 10 s) instead of spinning forever.

SMACC2 runs this loop in an async behavior's thread. Here it is a synchronous behavior polled by the
runtime (ISmaccUpdatable, every ``CONTROL_PERIOD_S`` of machine clock, on the executor thread): the
control steps then happen at the same sim times whatever the machine's load, where a thread sleeping
on the clock wakes up late, and late by a different amount on every run.
"""

from __future__ import annotations

import math

from smacc_py.clients.cl_nav2z.client import ClNav2Z
from smacc_py.clients.cl_nav2z.cp_pose import CpPose
from smacc_py.clients.cl_nav2z.geometry import Pose2D, normalize_angle
from smacc_py.core import ISmaccUpdatable, SmaccClientBehavior

CONTROL_PERIOD_S = 0.1  # 10 Hz, as SMACC2 (needs signal_detector_loop_freq >= 10 Hz to keep up)


class CbPureSpinning(SmaccClientBehavior, ISmaccUpdatable):
    """Spin ``yaw`` rad (sign = direction) at most ``max_w`` rad/s."""

    update_period_s = CONTROL_PERIOD_S

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
        self.finished = False

    def on_entry(self) -> None:
        self._client = self.requires_client(ClNav2Z)
        self._cp_pose = self.requires_component(CpPose)
        self._start_s = self._last_update_s = self.sm.now()  # next step one control period from now
        self._last: Pose2D | None = self._cp_pose.refresh()
        self._step()  # the first command at once, as SMACC2's loop

    def update(self) -> None:
        if not self.finished:
            self._step()

    def _step(self) -> None:
        """One control period: check the timeout, integrate the yaw turned, command or finish."""
        if self.sm.now() - self._start_s > self.timeout_s:
            self._finish(success=False)
            return
        pose = self._cp_pose.refresh()
        if pose is None:
            return
        if self._last is not None:
            self.traveled += normalize_angle(pose[2] - self._last[2])
        self._last = pose
        remaining = self.yaw - self.traveled
        if abs(remaining) < self.yaw_tolerance:
            self._finish(success=True)
            return
        self._client.publish_twist(0.0, max(-self.max_w, min(self.max_w, self.k_p * remaining)))

    def _finish(self, *, success: bool) -> None:
        self.finished = True
        self._client.publish_twist()
        if success:
            self.post_success_event(traveled=self.traveled)
        else:
            self.post_failure_event(
                traveled=self.traveled,
                reason=f"CbPureSpinning timed out after {self.timeout_s:.1f} s having turned "
                f"{math.degrees(self.traveled):.0f} of {math.degrees(self.yaw):.0f} deg",
            )

    def on_exit(self) -> None:
        client = getattr(self, "_client", None)
        if not self.finished and client is not None:  # cut short by the state's exit: stop the robot
            self.finished = True
            client.publish_twist()
