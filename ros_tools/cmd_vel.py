"""The velocity command publisher of nav_stack's controller_server, behavior_server and teleop, and
of smacc_py's ClNav2Z.

Nav2 Jazzy publishes geometry_msgs/Twist on ``cmd_vel`` unless ``enable_stamped_cmd_vel`` is true,
then TwistStamped (frame = robot base). A subscriber of the other type silently gets nothing, so
every publisher takes the same parameter as sim2d. A tool that is not told (``stamped=None``: teleop,
a state machine run by hand beside nav-bringup, which stamps in lockstep) follows the type the topic's
subscribers take, read from the ROS graph: the robot decides, as it does on a real TurtleBot4.
"""

from __future__ import annotations

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

#: Nav2's cmd_vel QoS: reliable, volatile, the last 10.
CMD_VEL_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE, history=HistoryPolicy.KEEP_LAST)
STAMPED_TYPE, TWIST_TYPE = "geometry_msgs/msg/TwistStamped", "geometry_msgs/msg/Twist"


def subscribers_take_stamped(node: Node, topic: str = "cmd_vel") -> bool | None:
    """Whether ``topic``'s subscribers take TwistStamped (True) or Twist (False); None while the graph
    shows no subscriber of either (not discovered yet)."""
    types = {info.topic_type for info in node.get_subscriptions_info_by_topic(node.resolve_topic_name(topic))}
    if STAMPED_TYPE in types:
        return True
    if TWIST_TYPE in types:
        return False
    return None


class CmdVelPublisher:
    """Publishes (vx, wz) as Twist or TwistStamped on ``topic``.

    ``stamped=None`` follows the subscribers' type (:func:`subscribers_take_stamped`), checked at each
    publication until a subscriber is known; until then it publishes Twist.
    """

    def __init__(self, node: Node, stamped: bool | None, frame_id: str = "base_link",
                 topic: str = "cmd_vel") -> None:
        self._node = node
        self._topic = topic
        self._follow = stamped is None
        self.stamped = bool(stamped)
        self.frame_id = frame_id
        self.publisher = node.create_publisher(TwistStamped if self.stamped else Twist, topic, CMD_VEL_QOS)

    def follow_subscribers(self) -> None:
        """When following: take the subscribers' type once the graph shows one (a new publisher if it
        differs, which must be discovered again before it delivers). A no-op otherwise."""
        if not self._follow:
            return
        takes = subscribers_take_stamped(self._node, self._topic)
        if takes is None:
            return
        self._follow = False
        if takes != self.stamped:
            self._node.destroy_publisher(self.publisher)
            self.stamped = takes
            self.publisher = self._node.create_publisher(TwistStamped if takes else Twist, self._topic,
                                                         CMD_VEL_QOS)
            kind = "TwistStamped" if takes else "Twist"
            self._node.get_logger().info(f"{self._topic}: the robot takes {kind}; publishing that")

    def publish(self, vx: float, wz: float, stamp_ns: int | None = None, vy: float = 0.0) -> None:
        """Publish (vx m/s, wz rad/s, and vy m/s for holonomic robots); a stamped command carries
        ``stamp_ns`` (node clock ns), else now.

        A controller passes the nominal time of its cycle: sim2d applies a stamped command at stamp +
        ``stamped_cmd_vel_delay``, so the stamp, not the arrival, decides when it takes effect.
        """
        self.follow_subscribers()
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

    def stop(self, stamp_ns: int | None = None) -> None:
        """Publish a zero command (stamped ``stamp_ns``, e.g. the cycle's nominal time, else now)."""
        self.publish(0.0, 0.0, stamp_ns)

    def destroy(self) -> None:
        self._node.destroy_publisher(self.publisher)
