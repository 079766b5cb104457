"""The viewer's layers for MPPI and the collision monitor over DDS: ``/trajectories`` (sphere markers,
thinned, one colour group per namespace), the zones the node ``collision_monitor`` publishes on topics
of its own naming (found by publisher, a polygon from another node is not one of them), and its
``collision_points_marker`` (one POINTS marker per source), each placed through TF (odom is one metre
from map here, so a layer that skipped TF would land in the wrong place)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.helpers.viewer_client import EventStream

pytestmark = pytest.mark.ros
WAIT = 20.0  # s; generous for a loaded 2-core machine


@pytest.fixture
def viewer(ros_context) -> Iterator[object]:
    from navsuite_tools.viewer.main import ViewerApp
    from navsuite_tools.viewer.params import ViewerParams

    params = ViewerParams(port=0, rate=10.0, discovery_period=0.2, max_poses=50)
    app = ViewerApp(params, context=ros_context).start()
    try:
        yield app
    finally:
        app.close()


@pytest.fixture
def stream(viewer) -> Iterator[EventStream]:
    events = EventStream(viewer.url)
    try:
        yield events
    finally:
        events.close()


def _marker(ns: str, kind: int, frame: str, rgb: tuple[float, float, float], xy: list[tuple[float, float]],
            marker_id: int = 0) -> object:
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker

    marker = Marker(ns=ns, id=marker_id, type=kind, action=Marker.ADD)
    marker.header.frame_id = frame
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = (*rgb, 1.0)
    if kind == Marker.SPHERE:
        marker.pose.position.x, marker.pose.position.y = xy[0]
    else:
        marker.points = [Point(x=x, y=y) for x, y in xy]
    return marker


def test_trajectories_collision_zones_and_points_reach_the_page(viewer, stream, spinning):
    from geometry_msgs.msg import Point32, PolygonStamped
    from visualization_msgs.msg import Marker, MarkerArray

    from tests.helpers import viewer_fakes as fakes

    monitor, costmap = spinning("collision_monitor"), spinning("fake_costmap")
    fakes.publish_static(monitor, [fakes.map_to_odom(1.0, 0.0, 0.0)])

    def zone(corners: list[tuple[float, float]]) -> PolygonStamped:
        msg = PolygonStamped()
        msg.header.frame_id = "odom"
        msg.polygon.points = [Point32(x=x, y=y) for x, y in corners]
        return msg

    blue, red = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)
    candidates = [_marker("Candidate Trajectories", Marker.SPHERE, "odom", blue, [(0.01 * k, 0.0)], k)
                  for k in range(200)]
    optimal = [_marker("Optimal Trajectory", Marker.SPHERE, "odom", red, [(0.1 * k, 0.5)], k)
               for k in range(20)]
    points = MarkerArray(markers=[_marker("collision_points_scan", Marker.POINTS, "odom", red,
                                          [(0.3, 0.0), (0.3, 0.1)])])
    produced = [
        (monitor, "/polygon_stop", zone([(0.3, 0.16), (0.3, -0.16), (0.0, -0.16), (0.0, 0.16)])),
        (monitor, "/PolygonSlow", zone([(0.6, 0.3), (0.6, -0.3), (0.0, -0.3)])),
        (costmap, "/not_a_zone", zone([(5.0, 5.0), (6.0, 5.0), (6.0, 6.0)])),
        (monitor, "/collision_monitor/collision_points_marker", points),
        (monitor, "/trajectories", MarkerArray(markers=candidates + optimal)),
    ]
    publishers = [(node.create_publisher(type(msg), topic, 10), msg) for node, topic, msg in produced]
    timer = monitor.create_timer(0.1, lambda: [pub.publish(msg) for pub, msg in publishers])
    wanted = {"trajectories", "collision_polygons", "collision_points"}
    try:
        latest = stream.wait_for(
            lambda s: wanted <= s.keys() and not any("error" in s[k] for k in wanted)
            and len(s["collision_polygons"]["polygons"]) == 2, WAIT, f"the layers {sorted(wanted)}")
    finally:
        monitor.destroy_timer(timer)
    zones = latest["collision_polygons"]["polygons"]
    assert set(zones) == {"/polygon_stop", "/PolygonSlow"}  # the costmap's polygon is not a zone
    assert zones["/polygon_stop"] == pytest.approx([1.3, 0.16, 1.3, -0.16, 1.0, -0.16, 1.0, 0.16], abs=1e-3)
    trajectories = latest["trajectories"]
    assert trajectories["count"] == 220
    groups = {g["ns"]: g for g in trajectories["groups"]}
    assert groups["Optimal Trajectory"]["color"] == "#ff0000"
    assert groups["Candidate Trajectories"]["color"] == "#0000ff"
    dots = sum(len(g["points"]) // 2 for g in trajectories["groups"])
    assert dots <= 50 + 1  # thinned to max_poses, each group in proportion
    assert groups["Optimal Trajectory"]["points"][:2] == pytest.approx([1.0, 0.5], abs=1e-3)  # odom → map
    (scan_points,) = latest["collision_points"]["groups"]
    assert scan_points["ns"] == "collision_points_scan"
    assert scan_points["points"] == pytest.approx([1.3, 0.0, 1.3, 0.1], abs=1e-3)
