"""``CpWaypointsVisualizer``: shows CpWaypointNavigator's waypoints in RViz (SMACC2's CpWaypointsVisualizer).

It publishes one visualization_msgs/MarkerArray on ``cp_waypoints_visualizer/visualization_markers``
(reliable, transient local, depth 1: latched, so an RViz started later still gets it): per waypoint
``i`` a sphere (namespace ``waypoints``, id ``i``, 0.1 m) at its pose and a text label (namespace
``waypoints_labels``, id ``i``, 0.3 m high, 0.3 m above it) reading its name, or ``waypoint_<i>``.
Waypoints behind the cursor (reached) are green, the others red.

SMACC2 publishes the spheres and the labels as two arrays on every update; on a latched topic of
depth 1 the second would replace the first, so here both go in one array. It is published again only
when the list or the cursor changed, checked every ``update_period_s`` of machine clock.
"""

from __future__ import annotations

from collections.abc import Sequence

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from smacc_py.clients.cl_nav2z.cp_pose import make_header, make_pose_stamped
from smacc_py.clients.cl_nav2z.cp_waypoint_navigator import CpWaypointNavigator
from smacc_py.clients.cl_nav2z.waypoints_io import Waypoint
from smacc_py.core import ISmaccComponent, ISmaccUpdatable
from smacc_py.ros.context import ros_context

MARKERS_TOPIC = "cp_waypoints_visualizer/visualization_markers"
LATCHED_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
SPHERE_DIAMETER_M = 0.1
LABEL_HEIGHT_M = 0.3  # text height, and how far above the waypoint it floats
REACHED = ColorRGBA(r=0.0, g=1.0, b=0.0, a=1.0)
PENDING = ColorRGBA(r=1.0, g=0.0, b=0.0, a=1.0)


def waypoint_markers(waypoints: Sequence[Waypoint], reached: int, frame_id: str,
                     stamp_s: float) -> MarkerArray:
    """Spheres and labels for ``waypoints`` in ``frame_id``; the first ``reached`` are green."""
    header = make_header(frame_id, stamp_s)
    markers = []
    for i, waypoint in enumerate(waypoints):
        pose = make_pose_stamped(frame_id, waypoint.x, waypoint.y, waypoint.yaw).pose
        color = REACHED if i < reached else PENDING
        sphere = Marker(header=header, ns="waypoints", id=i, type=Marker.SPHERE, action=Marker.ADD,
                        pose=pose, color=color)
        sphere.scale.x = sphere.scale.y = sphere.scale.z = SPHERE_DIAMETER_M
        label = Marker(header=header, ns="waypoints_labels", id=i, type=Marker.TEXT_VIEW_FACING,
                       action=Marker.ADD, pose=pose, color=color, text=waypoint.name or f"waypoint_{i}")
        label.pose.position.z = LABEL_HEIGHT_M
        label.scale.z = LABEL_HEIGHT_M
        markers += [sphere, label]
    return MarkerArray(markers=markers)


class CpWaypointsVisualizer(ISmaccComponent, ISmaccUpdatable):
    """Publishes the waypoints of the machine's CpWaypointNavigator (see the module docstring).

    Args:
        frame_id: the frame the waypoints are in (SMACC2: map).
        topic: the MarkerArray topic.
        update_period_s: s of machine clock between checks for a change.
    """

    def __init__(self, frame_id: str = "map", topic: str = MARKERS_TOPIC,
                 update_period_s: float = 0.5) -> None:
        self.frame_id, self.topic = frame_id, topic
        self.set_update_period(update_period_s)
        self.published: MarkerArray | None = None
        self._shown: tuple[int, tuple[Waypoint, ...]] | None = None

    def on_initialize(self) -> None:
        self._navigator = self.requires_component(CpWaypointNavigator)
        self._pub = ros_context(self.sm).node.create_publisher(MarkerArray, self.topic, LATCHED_QOS)

    def update(self) -> None:
        """Publish when the waypoints or the cursor changed since the last publication."""
        navigator = self._navigator
        shown = (navigator.current_index, tuple(navigator.waypoints))
        if shown != self._shown:
            self._shown = shown
            self.published = waypoint_markers(shown[1], shown[0], self.frame_id, self.sm.now())
            self._pub.publish(self.published)
