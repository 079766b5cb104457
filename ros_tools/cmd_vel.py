"""The velocity command publisher of nav_stack's controller_server, behavior_server and teleop, and
of smacc_py's ClNav2Z.

Nav2 Jazzy publishes geometry_msgs/Twist on ``cmd_vel`` unless ``enable_stamped_cmd_vel`` is true,
then TwistStamped (frame = robot base). A subscriber of the other type silently gets nothing, so
every publisher takes the same parameter as sim2d.
"""

from __future__ import annotations

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Nav2's cmd_vel QoS: reliable, volatile, the last 10.
CMD_VEL_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)


class CmdVelPublisher:
    """Publishes (vx, wz) as Twist or TwistStamped on ``topic``."""

    def __init__(self, node: Node, stamped: bool, frame_id: str = "base_link",
                 topic: str = "cmd_vel") -> None:
        self._node = node
        self.stamped = stamped
        self.frame_id = frame_id
        self.publisher = node.create_publisher(TwistStamped if stamped else Twist, topic, CMD_VEL_QOS)

    def publish(self, vx: float, wz: float, stamp_ns: int | None = None, vy: float = 0.0) -> None:
        """Publish (vx m/s, wz rad/s, and vy m/s for holonomic robots); a stamped command carries
        ``stamp_ns`` (node clock ns), else now.

        A controller passes the nominal time of its cycle: sim2d applies a stamped command at stamp +
        ``stamped_cmd_vel_delay``, so the stamp, not the arrival, decides when it takes effect.
        """
        twist = Twist()
        twist.linear.x, twist.linear.y, twist.angular.z = float(vx), float(vy), float(wz)
        if not self.stamped:
            self.publisher.publish(twist)
            return
        msg = TwistStamped()
        msg.header.frame_id = self.frame_id
        if stamp_ns is None:
            msg.header.stamp = self._node.get_clock().now().to_msg()
        else:
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
        msg.twist = twist
        self.publisher.publish(msg)

    def stop(self) -> None:
        """Publish a zero command."""
        self.publish(0.0, 0.0)

    def destroy(self) -> None:
        self._node.destroy_publisher(self.publisher)
