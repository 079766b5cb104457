"""What collision_monitor shows viewers: the data points it used (``~/collision_points_marker``) and its
zones (geometry_msgs/PolygonStamped on each zone's ``polygon_pub_topic``).

Why a module of its own: the node decides *when* to publish (someone listens, a zone has
``visualize``); these functions only say *what*, in Nav2 Jazzy's shape, so a viewer or RViz
configured for Nav2 reads ours unchanged:

* one POINTS marker per observation source, in the order of ``observation_sources``: namespace
  ``collision_points_<source>``, id 0, frame ``base_frame_id`` with stamp 0 (the newest transform),
  ``frame_locked``, points 0.02 m, opaque red, no lifetime, z = 0 (planar data). A disabled source
  gets an empty marker; the sources after an invalid one get none, as Nav2 stops reading there;
* a zone's outline as PolygonStamped in ``base_frame_id`` (a circle as its 16-gon).

Units: m.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Point32, PolygonStamped
from visualization_msgs.msg import Marker, MarkerArray

from nav_stack.core.geometry import FloatArray

MARKER_NAMESPACE = "collision_points_"  # + the source's name (Nav2 Jazzy)
POINT_SIZE = 0.02  # m, Nav2's marker.scale.x and .y


def collision_points_marker(base_frame: str,
                            points_by_source: Iterable[tuple[str, FloatArray]]) -> MarkerArray:
    """One POINTS marker per (source name, points (N, 2) in ``base_frame``)."""
    markers = []
    for name, points in points_by_source:
        marker = Marker(ns=MARKER_NAMESPACE + name, id=0, type=Marker.POINTS, action=Marker.ADD,
                        frame_locked=True)
        marker.header.frame_id = base_frame  # stamp stays 0
        marker.scale.x = marker.scale.y = POINT_SIZE
        marker.color.r, marker.color.a = 1.0, 1.0
        marker.points = [Point(x=float(x), y=float(y)) for x, y in points]
        markers.append(marker)
    return MarkerArray(markers=markers)


def polygon_stamped(base_frame: str, stamp: Time,
                    outline: Sequence[Sequence[float]] | FloatArray) -> PolygonStamped:
    """A zone's outline (M, 2) (m, base frame) as geometry_msgs/PolygonStamped."""
    msg = PolygonStamped()
    msg.header.frame_id, msg.header.stamp = base_frame, stamp
    msg.polygon.points = [Point32(x=float(x), y=float(y)) for x, y in outline]
    return msg
