"""bt_navigator's localization guard: is the robot's pose in the map trustworthy enough to navigate?

Why: with a lost pose the planner plans from the wrong place and the controller fails later with
errors that do not name the cause (issue 18: 0 of 10 goals in a depot, "confusing controller
errors"). The guard listens to what localization says about itself and bt_navigator asks it:

* ``amcl_pose`` (``localization_topic``; reliable, transient local as amcl publishes it): the
  position σ along the widest axis of its covariance, against ``max_localization_std`` (m). Any
  Nav2-style localizer publishes this, so the check works with nav2_amcl too. The default, 1.0 m,
  lets a fresh initial pose through (RViz and amcl_init_pose_publisher use σ 0.5 m) and stops a
  global localization's cloud spread over the map.
* ``/diagnostics``: the status ``amcl: localization`` (nav_stack/ros/localization/amcl_health.py); WARN
  carries amcl's cause, e.g. "few beams on walls: 3 of 60 beams returned within 3.5 m (< 20 %)".

A new goal is refused while either says no; a running goal ends once it has been untrusted for
longer than ``localization_grace_period`` (s, node clock: sim time in simulation), which lets a
short dip pass. Nothing is untrusted before a message arrives: with SLAM (no amcl_pose, no amcl
status) nothing changes, and ``localization_topic: ""`` switches the guard off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseWithCovarianceStamped

from nav_stack.core.localization.health import position_std
from nav_stack.ros.common.qos import DEFAULT, LATCHED
from nav_stack.ros.localization.amcl_messages import DIAGNOSTICS_TOPIC, LOCALIZATION_STATUS, covariance_3x3

NOT_TRUSTWORTHY = "localization is not trustworthy"


def untrusted_message(reason: str) -> str:
    """The goal result's error_msg for an untrusted pose (code UNKNOWN: Nav2 has no localization code)."""
    return f"{NOT_TRUSTWORTHY}: {reason}"


@dataclass(frozen=True)
class LocalizationGuardParams:
    """bt_navigator parameters of the guard (not in Nav2)."""

    localization_topic: str = "amcl_pose"  # "" disables the guard
    max_localization_std: float = 1.0  # m, position σ of the pose covariance (widest axis)
    localization_grace_period: float = 5.0  # s (node clock) a running goal tolerates an untrusted pose

    def __post_init__(self) -> None:
        if not self.max_localization_std > 0.0 or not math.isfinite(self.max_localization_std):
            raise ValueError(f"max_localization_std must be a finite number > 0 m, got "
                             f"{self.max_localization_std}")
        if not self.localization_grace_period >= 0.0:
            raise ValueError(f"localization_grace_period must be >= 0 s, got "
                             f"{self.localization_grace_period}")


class LocalizationGuard:
    """Tracks whether localization can be trusted, and since when it cannot (node clock, s)."""

    def __init__(self, node: Any, params: LocalizationGuardParams) -> None:
        self.node, self.params = node, params
        self._pose_reason: str | None = None
        self._status_reason: str | None = None
        self._untrusted_since: float | None = None
        self._subscriptions = [] if not params.localization_topic else [
            node.create_subscription(PoseWithCovarianceStamped, params.localization_topic, self._on_pose,
                                     LATCHED),
            node.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, self._on_diagnostics, DEFAULT),
        ]

    def trust(self) -> str | None:
        """None while the pose can be trusted, else why not (amcl's cause or the covariance)."""
        return self._status_reason or self._pose_reason

    def untrusted_past_grace(self, now: float) -> str | None:
        """The reason, once the pose has been untrusted for longer than the grace period at ``now`` (s)."""
        reason = self.trust()
        if reason is None or self._untrusted_since is None:
            return None
        return reason if now - self._untrusted_since > self.params.localization_grace_period else None

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        covariance = covariance_3x3(msg.pose.covariance)
        sigma = position_std(covariance) if np.all(np.isfinite(covariance)) else math.nan
        limit = self.params.max_localization_std
        self._pose_reason = (None if sigma <= limit else  # a NaN covariance is not trusted either
                             f"{self.params.localization_topic} position σ {sigma:.2f} m > {limit:.2f} m")
        self._changed()

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        for status in msg.status:
            if status.name == LOCALIZATION_STATUS:
                ok = status.level == DiagnosticStatus.OK
                self._status_reason = None if ok else status.message or "amcl reports degraded localization"
                self._changed()

    def _changed(self) -> None:
        if self.trust() is None:
            self._untrusted_since = None
        elif self._untrusted_since is None:
            self._untrusted_since = self.node.get_clock().now().nanoseconds * 1e-9

    def destroy(self) -> None:
        for subscription in self._subscriptions:
            self.node.destroy_subscription(subscription)
        self._subscriptions = []
