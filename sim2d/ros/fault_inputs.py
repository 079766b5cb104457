"""The topics that inject faults into the robot's own outputs: odometry slip and the loss of a topic.

Why topics with standard messages (as world_inputs.py): a scenario's injector, ``ros2 topic pub`` or
any test harness can drive them, and each takes effect at the sim time it arrives (within one
lockstep lead of the /clock the sender acted on, the sender being a lockstep participant).

  sub  sim2d/odometry_slip (std_msgs/Float64MultiArray, data [scale, duration]): for ``duration`` s of
       sim time the odometry integrates ``scale`` x the true motion (scale >= 0; 1 is no slip; a
       duration <= 0 ends a running slip)
  sub  sim2d/topic_loss (diagnostic_msgs/KeyValue, key: one of scan, odom, tf, battery_state; value:
       a duration in s of sim time as text): that output publishes nothing for so long (<= 0: back at once)

In a fleet (issue 48) both are each robot's, under its namespace (/robot1/sim2d/odometry_slip).

The callbacks only translate, check and log; the core (``Simulator.slip_odometry``, ``lose_topic``,
sim2d.core.disturbances) holds the logic. A bad message is refused with a warning naming it, never
a dead simulator.
"""

from __future__ import annotations

import math

from diagnostic_msgs.msg import KeyValue
from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_msgs.msg import Float64MultiArray

from sim2d.core.disturbances import LOSABLE_TOPICS
from sim2d.core.simulator import RobotSim

ODOMETRY_SLIP_TOPIC = "sim2d/odometry_slip"
TOPIC_LOSS_TOPIC = "sim2d/topic_loss"


class FaultInputs:
    """Subscribes ``node`` to the two fault topics (under ``prefix``: "" or ``robot1/``) and applies what
    arrives to ``sim``."""

    def __init__(self, node: Node, sim: RobotSim, qos: QoSProfile, prefix: str = "") -> None:
        self.node, self.sim = node, sim
        self.label = f"{prefix.rstrip('/')}: " if prefix else ""   # in log lines, after "sim2d: "
        node.create_subscription(Float64MultiArray, prefix + ODOMETRY_SLIP_TOPIC, self._on_slip, qos)
        node.create_subscription(KeyValue, prefix + TOPIC_LOSS_TOPIC, self._on_topic_loss, qos)

    def _on_slip(self, msg: Float64MultiArray) -> None:
        logger = self.node.get_logger()
        values = list(msg.data)
        if len(values) != 2 or not all(math.isfinite(v) for v in values) or values[0] < 0.0:
            logger.warning(f"sim2d: {self.label}odometry slip {values} refused: expected "
                           "[scale >= 0, duration s]")
            return
        scale, duration = values
        self.sim.slip_odometry(scale, duration)
        state = f"x{scale:g} for {duration:g} s of sim time" if duration > 0 else "ended"
        logger.info(f"sim2d: {self.label}odometry slip {state} at sim time {self.sim.time:.3f} s")

    def _on_topic_loss(self, msg: KeyValue) -> None:
        logger = self.node.get_logger()
        topic = msg.key.lstrip("/")
        try:
            duration = float(msg.value)
        except ValueError:
            duration = math.nan
        if topic not in LOSABLE_TOPICS or not math.isfinite(duration):
            logger.warning(f"sim2d: {self.label}topic loss of {msg.key!r} for {msg.value!r} s refused: "
                           f"expected a topic of {', '.join(LOSABLE_TOPICS)} and a finite duration in s")
            return
        self.sim.lose_topic(topic, duration)
        state = f"for {duration:g} s of sim time" if duration > 0 else "ended"
        logger.info(f"sim2d: {self.label}topic loss of {topic} {state} at sim time {self.sim.time:.3f} s "
                    "(nothing sent)")
