"""What amcl tells the world about its own localization health (nav_stack/core/localization/health.py).

Why a module of its own: amcl_node schedules the filter; the core's HealthMonitor judges each
update; this part only turns the judgement into what a user and the navigator see:

* one warning when localization degrades, ``localization degraded: <cause>`` (the cause names
  its numbers), and one info line when it recovers: no repeated warnings while it lasts;
* ``/diagnostics`` (diagnostic_msgs/DiagnosticArray, reliable and volatile like diagnostic_updater)
  with the status ``amcl: localization``: level OK or WARN, message "localized" or the cause, and
  the latest numbers as key/values. Sent after every filter update and re-sent every
  REPUBLISH_PERIOD (wall), so a listener that starts late (bt_navigator's localization guard, an
  aggregator) learns the state even while the robot stands still and the filter does not update.

Parameters: ``health.<field>`` of HealthParams (amcl_params.py; config/nav2_params.yaml, amcl).
"""

from __future__ import annotations

from typing import Any

from diagnostic_msgs.msg import DiagnosticArray
from rclpy.clock import Clock, ClockType

from nav_stack.core.geometry import Pose2D
from nav_stack.core.localization import Amcl, PoseEstimate
from nav_stack.core.localization.health import HealthMonitor, HealthParams, LocalizationState, measure
from nav_stack.ros.common.qos import DEFAULT
from nav_stack.ros.localization.amcl_messages import DIAGNOSTICS_TOPIC, health_msg

REPUBLISH_PERIOD = 1.0  # s (wall), diagnostic_updater's default period


class HealthReport:
    """Judges each filter update with a HealthMonitor, logs state changes once, publishes /diagnostics."""

    def __init__(self, node: Any, params: HealthParams) -> None:
        self.node = node
        self.monitor = HealthMonitor(params)
        self._reported = False  # nothing to re-send before the first report
        self._pub = node.create_publisher(DiagnosticArray, DIAGNOSTICS_TOPIC, DEFAULT)
        self._timer = node.create_timer(REPUBLISH_PERIOD, self._republish,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))

    def observe(self, amcl: Amcl, estimate: PoseEstimate, stamp: float) -> None:
        """Judge the update that produced ``estimate`` from the scan at ``stamp`` (sim s)."""
        if amcl.last_beams is None:
            return
        sample = measure(amcl.distance_field, amcl.last_beams, Pose2D(estimate.x, estimate.y, estimate.yaw),
                         estimate.covariance, self.monitor.params.match_distance)
        if self.monitor.update(sample):
            if self.monitor.state is LocalizationState.DEGRADED:
                self.node.get_logger().warning(f"localization degraded: {self.monitor.cause}")
            else:
                self.node.get_logger().info(f"localization recovered: {sample.describe()}")
        self._publish(stamp)

    def reset(self, source: str) -> None:
        """A new initial pose from ``source``: start over as OK (the user says where the robot is)."""
        if self.monitor.state is LocalizationState.DEGRADED:
            self.node.get_logger().info(f"localization health reset by the initial pose from {source}")
        self.monitor.reset()
        self._publish()

    def _publish(self, stamp: float | None = None) -> None:
        """Send the current state, stamped ``stamp`` (sim s) or now."""
        self._reported = True
        now = self.node.get_clock().now().nanoseconds * 1e-9 if stamp is None else stamp
        self._pub.publish(health_msg(self.monitor, now))

    def _republish(self) -> None:
        if self._reported:
            self._publish()

    def destroy(self) -> None:
        self.node.destroy_timer(self._timer)
        self.node.destroy_publisher(self._pub)
