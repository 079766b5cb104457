"""The viewer node + HTTP server against fake publishers: page, SSE layers, clicks, throttling."""

from __future__ import annotations

import base64
import itertools
import math
import threading
from collections.abc import Iterator

import numpy as np
import pytest

from tests.helpers.viewer_client import EventStream, get, post_json

pytestmark = pytest.mark.ros
WAIT = 20.0  # s; generous for a loaded 2-core machine


@pytest.fixture
def viewer(ros_context) -> Iterator[object]:
    from navsuite_tools.viewer.main import ViewerApp
    from navsuite_tools.viewer.params import ViewerParams

    app = ViewerApp(ViewerParams(port=0, rate=10.0, discovery_period=0.2), context=ros_context).start()
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


def test_page_and_static_files_are_served(viewer):
    status, ctype, body = get(viewer.url)
    assert status == 200 and ctype.startswith("text/html")
    assert '<canvas id="map"' in body and "/static/viewer.js" in body
    for name in ("viewer.js", "panels.js", "style.css"):
        assert get(viewer.url + "static/" + name)[0] == 200, name
    assert get(viewer.url + "static/../server.py")[0] == 404
    assert get(viewer.url + "nowhere")[0] == 404


def test_stream_delivers_map_scan_robot_battery_and_state_machine(viewer, stream, spinning):
    from nav_msgs.msg import OccupancyGrid, Odometry
    from sensor_msgs.msg import BatteryState, LaserScan

    from ros_tools.tf.transform import Transform
    from tests.helpers.viewer_fakes import LATCHED, FakeSmacc, bt_log, occupancy_grid, publish_static

    node = spinning("fake_stack")
    cells = np.zeros((10, 20), dtype=np.int8)
    cells[0, 0], cells[9, 19], cells[5, 3] = 100, -1, 42
    node.create_publisher(OccupancyGrid, "/map", LATCHED).publish(occupancy_grid(cells, 0.1, (-1.0, -0.5)))
    publish_static(node, [("map", "odom", Transform.from_xy_yaw(1.0, 0.0, 0.0)),
                          ("odom", "base_scan", Transform.from_xy_yaw(0.0, 0.0, math.pi / 2))])
    scan = LaserScan(angle_min=0.0, angle_increment=math.pi / 2, range_min=0.1, range_max=3.5,
                     ranges=[1.0, math.inf, 0.05, 2.0])  # inf: no return, 0.05 < range_min: dropped
    scan.header.frame_id = "base_scan"
    truth = Odometry()
    truth.header.frame_id = "map"
    truth.pose.pose.position.x, truth.pose.pose.position.y = -2.0, -0.5
    truth.pose.pose.orientation.z, truth.pose.pose.orientation.w = math.sin(0.25), math.cos(0.25)
    battery = BatteryState(percentage=0.5, voltage=12.0)
    publishers = [(node.create_publisher(type(msg), topic, 10), msg)
                  for topic, msg in (("/scan", scan), ("/ground_truth", truth), ("/battery_state", battery))]
    smacc = FakeSmacc(node)
    bt = node.create_publisher(type(bt_log([])), "/behavior_tree_log", 10)

    def publish_all() -> None:
        for pub, msg in publishers:
            pub.publish(msg)
        smacc.publish()

    timer = node.create_timer(0.1, publish_all)
    try:
        wanted = {"map", "scan", "truth", "battery", "sm:/sm_fake"}
        latest = stream.wait_for(lambda s: wanted <= s.keys() and "points" in s["scan"], WAIT,
                                 "map, scan, robot, battery and smacc layers")
        grid = latest["map"]
        assert (grid["width"], grid["height"], grid["origin"]) == (20, 10, [-1.0, -0.5, 0.0])
        assert grid["resolution"] == pytest.approx(0.1)
        raw = np.frombuffer(base64.b64decode(grid["data"]), dtype=np.uint8).reshape(10, 20)
        # row 0 stays the bottom row; the int8 -1 (unknown) travels as 255
        assert (raw[0, 0], raw[9, 19], raw[5, 3], raw[1, 1]) == (100, 255, 42, 0)
        # base_scan is odom rotated +90°, odom is map shifted +1 m in x: beam 0 (1 m along +x) → (1, 1),
        # beam 3 (2 m along -y of base_scan = +x of odom) → (3, 0)
        assert stream.latest["scan"]["points"] == pytest.approx([1.0, 1.0, 3.0, 0.0], abs=1e-3)
        assert latest["truth"]["pose"] == pytest.approx([-2.0, -0.5, 0.5], abs=1e-3)
        assert latest["battery"]["percentage"] == pytest.approx(0.5)

        # description and status are two topics: the graph may come before the current state (CI run CV)
        sm = stream.wait_for(lambda s: s["sm:/sm_fake"]["nodes"] and s["sm:/sm_fake"]["current"], WAIT,
                             "state machine graph and current state")["sm:/sm_fake"]
        layers = {n["id"]: n["layer"] for n in sm["nodes"]}
        assert layers == {"StAcquireSensors": 0, "StNavigate": 1, "StRecover": 2, "StDock": 2}
        assert sm["current"] == ["StAcquireSensors"]
        smacc.transition("StNavigate", "SUCCESS", "EvCbSuccess")
        sm = stream.wait_for(lambda s: s["sm:/sm_fake"]["transitions"]
                             and s["sm:/sm_fake"]["current"] == ["StNavigate"], WAIT,
                             "a transition and the new current state")["sm:/sm_fake"]
        last = sm["transitions"][-1]
        assert (last["source"], last["target"], last["tag"]) == ("StAcquireSensors", "StNavigate", "SUCCESS")

        bt.publish(bt_log([("NavigateRecovery", 1, "IDLE", "RUNNING"),
                           ("ComputePathToPose", 5, "IDLE", "RUNNING")]))
        bt.publish(bt_log([("ComputePathToPose", 5, "RUNNING", "SUCCESS")]))
        latest = stream.wait_for(lambda s: "bt" in s and s["bt"]["batches"] == 2, WAIT, "two BT logs")
        nodes = latest["bt"]["nodes"]
        assert [(n["name"], n["status"]) for n in nodes] == [("NavigateRecovery", "RUNNING"),
                                                             ("ComputePathToPose", "SUCCESS")]
    finally:
        node.destroy_timer(timer)


def test_stream_delivers_particles_plans_local_costmap_footprint_waypoints_and_nav_status(
        viewer, stream, spinning):
    """The navigation layers, each from its own topic with the producer's QoS and frame: AMCL's best-effort
    cloud, the planner's /plan (map), the controller's /local_plan and the local costmap with its footprint
    (odom, one metre from map here, so a layer that skipped TF would land in the wrong place), the RViz
    panel's waypoint markers (labels dropped) and navigate_to_pose's status (the newest goal counts)."""
    from action_msgs.msg import GoalStatus

    from tests.helpers import viewer_fakes as fakes

    node = spinning("fake_navigation")
    fakes.publish_static(node, [fakes.map_to_odom(1.0, 0.0, 0.0)])
    produced = {  # topic → (message, the producer's QoS), republished as costmaps and controllers do
        "/particle_cloud": (fakes.particle_cloud([(0.5, 0.0, 0.0), (0.6, 0.1, 1.0), (0.4, -0.1, -1.0)]),
                            fakes.BEST_EFFORT),
        "/plan": (fakes.path([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.5, 0.5)]), 10),
        "/local_plan": (fakes.path([(0.0, 0.0, 0.0), (0.5, 0.0, 0.0)], frame="odom"), 10),
        "/local_costmap/costmap": (fakes.marker_costmap(3.0, 0.05, (0.5, 0.5), frame="odom"), fakes.LATCHED),
        "/local_costmap/published_footprint": (
            fakes.footprint([(0.2, 0.2), (-0.2, 0.2), (-0.2, -0.2), (0.2, -0.2)]), 10),
        "/waypoints": (fakes.waypoint_markers([(1.0, 1.0, 0.0), (2.0, -1.0, 1.5)]), 10),
        "/navigate_to_pose/_action/status": (fakes.goal_statuses(
            [(GoalStatus.STATUS_SUCCEEDED, 3), (GoalStatus.STATUS_EXECUTING, 5)]), fakes.ACTION_STATUS),
    }
    publishers = [(node.create_publisher(type(msg), topic, qos), msg)
                  for topic, (msg, qos) in produced.items()]
    timer = node.create_timer(0.1, lambda: [pub.publish(msg) for pub, msg in publishers])
    wanted = {"particles", "plan", "local_plan", "local_costmap", "footprint", "waypoints", "nav_status"}
    try:  # a message converted before /tf_static arrived shows a TF error until the next one
        latest = stream.wait_for(lambda s: wanted <= s.keys() and not any("error" in s[k] for k in wanted),
                                 WAIT, f"the layers {sorted(wanted)} without errors")
    finally:
        node.destroy_timer(timer)
    assert latest["particles"]["count"] == 3
    assert latest["particles"]["poses"] == pytest.approx([0.5, 0.0, 0.0, 0.6, 0.1, 1.0, 0.4, -0.1, -1.0],
                                                         abs=1e-3)
    assert latest["plan"] == {"count": 3, "poses": pytest.approx([0, 0, 0, 1, 0, 0, 2, 0.5, 0.5], abs=1e-3)}
    assert latest["local_plan"]["poses"] == pytest.approx([1.0, 0.0, 0.0, 1.5, 0.0, 0.0], abs=1e-3)
    grid = latest["local_costmap"]
    assert (grid["frame"], grid["width"], grid["height"]) == ("odom", 60, 60)
    assert grid["origin"] == pytest.approx([-0.5, -1.5, 0.0])  # (-1.5, -1.5) in odom
    raw = np.frombuffer(base64.b64decode(grid["data"]), dtype=np.uint8).reshape(60, 60)
    assert raw[40, 40] == 100 and raw[20, 20] == 0  # the lethal block at (0.5, 0.5) odom, row 0 at the bottom
    corners = [1.2, 0.2, 0.8, 0.2, 0.8, -0.2, 1.2, -0.2]  # the outline, shifted by odom's offset
    assert latest["footprint"]["points"] == pytest.approx(corners, abs=1e-3)
    assert latest["waypoints"]["poses"] == pytest.approx([1.0, 1.0, 0.0, 2.0, -1.0, 1.5], abs=1e-3)
    assert latest["nav_status"] == {"status": "EXECUTING", "goals": 2}
    assert latest["info"]["topics"]["/particle_cloud"]["reliability"] == "best_effort"


def test_pose_estimate_and_goal_clicks_publish(viewer, spinning):
    from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped

    from navsuite_testing.ros import wait_until

    node = spinning("click_listener")
    got: dict[str, object] = {}
    node.create_subscription(PoseWithCovarianceStamped, "/initialpose",
                             lambda m: got.setdefault("initial", m), 10)
    node.create_subscription(PoseStamped, "/goal_pose", lambda m: got.setdefault("goal", m), 10)
    wait_until(lambda: node.count_publishers("/initialpose") and node.count_publishers("/goal_pose"), WAIT,
               "viewer publishers")

    status, reply = post_json(viewer.url + "api/initial_pose", {"x": 1.5, "y": -0.5, "yaw": 0.5})
    assert (status, reply["topic"]) == (200, "/initialpose")
    status, reply = post_json(viewer.url + "api/goal", {"x": -1.0, "y": 2.0, "yaw": -math.pi / 2})
    assert (status, reply["topic"]) == (200, "/goal_pose")
    wait_until(lambda: {"initial", "goal"} <= got.keys(), WAIT, "/initialpose and /goal_pose messages")

    initial, goal = got["initial"], got["goal"]
    assert initial.header.frame_id == "map" and goal.header.frame_id == "map"
    p = initial.pose.pose
    assert (p.position.x, p.position.y) == (1.5, -0.5)
    assert 2 * math.atan2(p.orientation.z, p.orientation.w) == pytest.approx(0.5)
    cov = list(initial.pose.covariance)
    assert (cov[0], cov[7], cov[35]) == pytest.approx((0.25, 0.25, 0.0685389), abs=1e-6)
    assert sum(abs(c) for c in cov) == pytest.approx(0.25 + 0.25 + 0.06853891945200942)
    assert (goal.pose.position.x, goal.pose.position.y) == (-1.0, 2.0)
    assert 2 * math.atan2(goal.pose.orientation.z, goal.pose.orientation.w) == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize(("body", "field"), [
    ({"x": 1, "y": "a", "yaw": 0}, "'y'"),
    ({"x": 1, "y": 2}, "'yaw'"),
    ({"x": float("inf"), "y": 0, "yaw": 0}, "'x'"),
    ([1, 2, 3], "object"),
])
def test_bad_click_bodies_are_refused_with_the_field_named(viewer, body, field):
    status, reply = post_json(viewer.url + "api/goal", body)
    assert status == 400 and field in reply["error"]


def test_a_1khz_topic_reaches_the_browser_at_most_at_the_rate(viewer, stream, spinning):
    """Latest-value-only: a 1 kHz battery topic yields batches ≥ 1/rate apart (server clock), far fewer
    than the messages sent, and the last value published is the one the page ends with."""
    from sensor_msgs.msg import BatteryState

    node = spinning("fast_battery")
    pub = node.create_publisher(BatteryState, "/battery_state", 10)
    sent = {"n": 0}
    stop = threading.Event()

    def tick() -> None:
        if not stop.is_set():
            sent["n"] += 1
            pub.publish(BatteryState(percentage=sent["n"] / 1e6))

    timer = node.create_timer(0.001, tick)
    try:
        stream.wait_for(lambda s: sent["n"] >= 1000 and len(stream.layer_batches("battery")) >= 5, WAIT * 3,
                        "1000 messages and 5 batches")
    finally:
        stop.set()
        node.destroy_timer(timer)
    final = sent["n"] / 1e6
    stream.wait_for(lambda s: s.get("battery", {}).get("percentage") == pytest.approx(final, abs=1e-9), WAIT,
                    "the last published value")
    stamps = [b["t"] for b in stream.batches]
    assert all(b - a >= 0.1 - 1e-6 for a, b in itertools.pairwise(stamps)), stamps
    received = len(stream.layer_batches("battery"))
    assert received < sent["n"] / 5, (received, sent["n"])


def test_the_command_serves_on_a_free_port_and_stops_on_ctrl_c():
    """``python -m navsuite_tools.viewer.main --port 0`` prints its URL, serves the page, exits 0 on
    SIGINT."""
    from navsuite_testing.ros import start_python, stop_process, wait_until

    proc = start_python("navsuite_tools.viewer.main", ["--port", "0", "--rate", "5"])
    lines: list[str] = []
    reader = threading.Thread(target=lambda: lines.extend(proc.stdout), daemon=True)
    reader.start()
    try:
        wait_until(lambda: any(line.startswith("viewer: http://127.0.0.1:") for line in lines)
                   or proc.poll() is not None, WAIT, "the URL line")
        url = next(line for line in lines if line.startswith("viewer: ")).split()[1]
        assert get(url)[0] == 200
    finally:
        stop_process(proc)
        reader.join(timeout=5.0)
    assert proc.returncode == 0, "".join(lines)
