"""collision_monitor over DDS on a /clock this test drives, with static TF (odom → base_footprint →
base_scan) and fake sensors:

* a LaserScan: no scan yet stops the robot ("invalid source"); a wall 0.3 m ahead stops it (state
  names the stop polygon); at 0.7 m only the circle slows it, as at 0.3 m with the stop polygon
  switched off at run time; gone, 0.3 m/s passes unchanged; a scan that stops coming stops the
  robot once it is older than source_timeout ("invalid source", the log names the source); a zero
  input is published for stop_pub_timeout, then the node falls silent; the polygon and the collision
  points (Jazzy's marker: one per source, namespace collision_points_<source>) are published for
  viewers;
* a synthetic PointCloud2 with TwistStamped: an approach polygon shaped by a footprint topic slows
  the robot, a floor point below min_height is ignored, a point in the stop polygon stops it, and
  the output keeps the input's stamp and frame; a zone with ``visualize`` and no polygon_pub_topic
  is published on its own name (Jazzy's default);
* bad parameters fail configure naming the parameter and the value;
* the sources' transform: base shift correction through odom, within transform_tolerance.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.msg")

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point32, PolygonStamped, Twist, TwistStamped
from nav2_msgs.msg import CollisionMonitorState
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan, PointCloud2, PointField
from visualization_msgs.msg import MarkerArray

from nav_stack.ros.collision.collision_monitor import CollisionMonitorNode, build_nodes
from nav_stack.ros.collision.collision_monitor_sources import SourceFrames
from nav_stack.ros.common.qos import DEFAULT, SENSOR
from navsuite_testing.nav.world import Harness
from navsuite_testing.ros import wait_until
from ros_tools.cmd_vel import CMD_VEL_QOS
from ros_tools.tf import Transform, TransformBuffer, TransformError
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg

pytestmark = pytest.mark.ros

TICK_NS = 50_000_000  # sim time per step: one command, one sensor message
START_NS = 100_000_000_000
SCAN_IN_BASE = (-0.064, 0.0, 0.122)  # the waffle's base_scan mount
STOP_ZONE = "[[0.4, 0.3], [0.4, -0.3], [0.0, -0.3], [0.0, 0.3]]"


def _time(ns: int) -> Time:
    sec, nanosec = divmod(ns, 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


def wall_scan(distance: float | None) -> list[float]:
    """360 beams from base_scan: a wall across x = ``distance`` (base frame) within ±15°, else free."""
    ranges = [math.inf] * 360
    if distance is not None:
        for i in list(range(16)) + list(range(345, 360)):
            ranges[i] = (distance - SCAN_IN_BASE[0]) / math.cos(math.radians(i))
    return ranges


def cloud_msg(points: list[tuple[float, float, float]], frame: str, stamp: Time) -> PointCloud2:
    """x, y, z, intensity float32 (16-byte points) in ``frame``."""
    data = np.array([(x, y, z, 1.0) for x, y, z in points], dtype="<f4")
    msg = PointCloud2(height=1, width=len(points), is_bigendian=False, point_step=16,
                      row_step=16 * len(points), is_dense=True)
    msg.fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                  for i, n in enumerate(("x", "y", "z", "intensity"))]
    msg.header.frame_id, msg.header.stamp = frame, stamp
    msg.data = data.tobytes()
    return msg


class Probe(Node):
    """Drives /clock and static TF, publishes sensors and commands, records the monitor's outputs."""

    def __init__(self, context: Any, stamped: bool, server_now: Callable[[], int]) -> None:
        super().__init__("collision_monitor_probe", context=context)
        self.stamped, self.server_now, self.now_ns = stamped, server_now, START_NS
        self.clock_pub = self.create_publisher(Clock, "/clock", 10)
        self.scan_pub = self.create_publisher(LaserScan, "scan", SENSOR)
        self.cloud_pub = self.create_publisher(PointCloud2, "points", SENSOR)
        self.footprint_pub = self.create_publisher(PolygonStamped, "local_costmap/published_footprint",
                                                   DEFAULT)
        kind = TwistStamped if stamped else Twist
        self.cmd_pub = self.create_publisher(kind, "cmd_vel_smoothed", CMD_VEL_QOS)
        self.outputs: list[Any] = []
        self.outcomes: list[Any] = []   # the node's monitor outcomes, see count_outcomes
        self.states: list[CollisionMonitorState] = []
        self.polygons: list[PolygonStamped] = []
        self.markers: list[MarkerArray] = []
        self.subs = [self.create_subscription(kind, "cmd_vel", self.outputs.append, CMD_VEL_QOS),
                     self.create_subscription(CollisionMonitorState, "collision_monitor_state",
                                              self.states.append, DEFAULT)]
        self.named_polygons: list[PolygonStamped] = []
        self.extra = [self.create_subscription(PolygonStamped, "polygon_stop", self.polygons.append, DEFAULT),
                      self.create_subscription(PolygonStamped, "PolygonStop", self.named_polygons.append,
                                               DEFAULT),
                      self.create_subscription(MarkerArray, "collision_monitor/collision_points_marker",
                                               self.markers.append, DEFAULT)]
        self.tf_static = StaticTransformBroadcaster(self)
        stamp = _time(0)
        scan_mount = Transform(*SCAN_IN_BASE)
        self.tf_static.send([transform_to_msg(Transform(), "odom", "base_footprint", stamp),
                             transform_to_msg(scan_mount, "base_footprint", "base_scan", stamp)])

    def tick(self) -> None:
        """Advance sim time one step and wait until the monitor's clock reads it."""
        self.now_ns += TICK_NS
        self.clock_pub.publish(Clock(clock=_time(self.now_ns)))
        wait_until(lambda: self.server_now() >= self.now_ns, 10.0, "the node clock to follow /clock",
                   step=0.001)

    def scan(self, distance: float | None) -> None:
        msg = LaserScan(angle_min=0.0, angle_max=math.radians(359), angle_increment=math.radians(1),
                        range_min=0.12, range_max=3.5, ranges=wall_scan(distance))
        msg.header.frame_id, msg.header.stamp = "base_scan", _time(self.now_ns)
        self.scan_pub.publish(msg)

    def command(self, vx: float) -> None:
        twist = Twist()
        twist.linear.x = vx
        if not self.stamped:
            self.cmd_pub.publish(twist)
            return
        msg = TwistStamped(twist=twist)
        msg.header.frame_id, msg.header.stamp = "base_link", _time(self.now_ns - 7)
        self.cmd_pub.publish(msg)

    def scan_and_command(self, distance: float | None, vx: float) -> None:
        self.scan(distance)
        self.command(vx)

    def vx(self, k: int = -1) -> float:
        out = self.outputs[k]
        return float((out.twist if self.stamped else out).linear.x)

    def count_outcomes(self, monitor: Any) -> None:
        """Record each outcome of ``monitor.process`` (one per command the node took), so a step waits
        exactly for what the node sent rather than a fixed time for a reply that may not come."""
        process = monitor.process

        def counted(*args: Any, **kwargs: Any) -> Any:
            outcome = process(*args, **kwargs)
            self.outcomes.append(outcome)
            return outcome
        monitor.process = counted

    def mark(self) -> tuple[int, int, int]:
        """How many outcomes, outputs and states there are now (for :meth:`settle`)."""
        return len(self.outcomes), len(self.outputs), len(self.states)

    def settle(self, mark: tuple[int, int, int], commands: int) -> None:
        """Wait until the node has taken ``commands`` commands since ``mark``, and every output and
        state message those produced has arrived here."""
        done, outputs, states = mark
        wait_until(lambda: len(self.outcomes) >= done + commands, 10.0, "the monitor to take the command",
                   step=0.001)
        new = self.outcomes[done:done + commands]
        published, changed = sum(o.publish for o in new), sum(o.state_changed for o in new)
        wait_until(lambda: len(self.outputs) >= outputs + published and len(self.states) >= states + changed,
                   10.0, "the monitor's output and state", step=0.001)

    def step_until(self, predicate: Callable[[], bool], what: str, send: Callable[[], None],
                   ticks: int = 100) -> None:
        """Tick, ``send()`` (sensors and a command), until ``predicate()`` holds after the node took it."""
        for _ in range(ticks):
            self.tick()
            mark = self.mark()
            send()
            self.settle(mark, 1)
            if predicate():
                return
        raise AssertionError(f"no {what} within {ticks} steps; last outputs "
                             f"{[round(self.vx(k), 4) for k in range(-min(5, len(self.outputs)), 0)]}, "
                             f"states {[(s.action_type, s.polygon_name) for s in self.states]}")


def bring_up(context: Any, stamped: bool, params: list[Parameter]) -> tuple[Harness, Probe, Any]:
    harness = Harness(context)
    (server,) = build_nodes(use_sim_time=True, context=context, parameter_overrides=[
        Parameter("enable_stamped_cmd_vel", value=stamped),
        Parameter("state_topic", value="collision_monitor_state"), *params])
    probe = Probe(context, stamped, lambda: server.get_clock().now().nanoseconds)
    harness.add(server, probe)
    probe.clock_pub.publish(Clock(clock=_time(START_NS)))
    wait_until(lambda: server.get_clock().now().nanoseconds == START_NS, 20.0, "the first /clock")
    harness.bring_up(server)
    probe.count_outcomes(server.monitor)
    wait_until(lambda: probe.cmd_pub.get_subscription_count() > 0
               and all(s.get_publisher_count() > 0 for s in probe.subs), 20.0, "cmd_vel and state discovery")
    return harness, probe, server


@pytest.fixture
def scan_rig(ros_context: Any) -> Iterator[tuple[Probe, Any]]:
    harness = None
    try:
        harness, probe, server = bring_up(ros_context, False, [
            Parameter("polygons", value=["PolygonStop", "PolygonSlow"]),
            Parameter("PolygonStop.type", value="polygon"),
            Parameter("PolygonStop.points", value=STOP_ZONE),
            Parameter("PolygonStop.action_type", value="stop"),
            Parameter("PolygonStop.visualize", value=True),
            Parameter("PolygonStop.polygon_pub_topic", value="polygon_stop"),
            Parameter("PolygonSlow.type", value="circle"), Parameter("PolygonSlow.radius", value=1.0),
            Parameter("PolygonSlow.action_type", value="slowdown"),
            Parameter("observation_sources", value=["scan"]), Parameter("scan.topic", value="scan")])
        yield probe, server
    finally:
        if harness is not None:
            harness.close()


def test_a_scan_obstacle_stops_or_slows_the_command_and_a_clear_path_passes_it(
        scan_rig: tuple[Probe, Any], capfd: Any) -> None:
    probe, server = scan_rig
    stopped = (1, "PolygonStop")

    def state() -> tuple[int, str]:
        return (probe.states[-1].action_type, probe.states[-1].polygon_name) if probe.states else (-1, "")

    probe.step_until(lambda: state() == (1, "invalid source"), "stop for a missing scan",
                     lambda: probe.command(0.3))
    assert probe.vx() == 0.0
    probe.step_until(lambda: bool(probe.polygons), "the stop polygon for viewers", lambda: probe.command(0.3))
    assert [c for p in probe.polygons[-1].polygon.points for c in (p.x, p.y)] == pytest.approx(
        [0.4, 0.3, 0.4, -0.3, 0.0, -0.3, 0.0, 0.3])
    assert probe.polygons[-1].header.frame_id == "base_footprint"

    def send(distance: float | None) -> Callable[[], None]:
        return functools.partial(probe.scan_and_command, distance, 0.3)

    probe.step_until(lambda: state() == stopped, "stop for a wall at 0.3 m", send(0.3))
    probe.step_until(lambda: probe.vx() == 0.0, "a zero command", send(0.3))
    probe.step_until(lambda: state() == (2, "PolygonSlow"), "slowdown for a wall at 0.7 m", send(0.7))
    probe.step_until(lambda: probe.vx() == pytest.approx(0.15), "half speed", send(0.7))
    probe.step_until(lambda: bool(probe.markers and probe.markers[-1].markers[0].points), "collision points",
                     send(0.7))
    (marker,) = probe.markers[-1].markers  # one source: one marker
    assert (marker.header.frame_id, marker.ns, marker.id, marker.type) == ("base_footprint",
                                                                           "collision_points_scan", 0, 8)
    assert (marker.header.stamp.sec, marker.header.stamp.nanosec, marker.frame_locked) == (0, 0, True)
    assert (marker.scale.x, marker.color.r, marker.color.g, marker.color.a) == pytest.approx((0.02, 1, 0, 1))
    assert min(p.x for p in marker.points) == pytest.approx(0.7, abs=1e-3)  # the wall, in the base frame
    # Run-time <polygon>.enabled, as Nav2 takes it: without the stop zone, the circle slows.
    assert server.set_parameters([Parameter("PolygonStop.enabled", value=False)])[0].successful
    probe.step_until(lambda: state() == (2, "PolygonSlow") and probe.vx() == pytest.approx(0.15),
                     "slowdown with the stop zone off", send(0.3))
    assert server.set_parameters([Parameter("PolygonStop.enabled", value=True)])[0].successful
    probe.step_until(lambda: state() == stopped, "stop with the stop zone on again", send(0.3))
    probe.step_until(lambda: state() == (0, ""), "normal operation without the wall", send(None))
    probe.step_until(lambda: probe.vx() == 0.3, "the command unchanged", send(None))

    # The scan stops coming (a hung driver): once its newest data is older than source_timeout (2 s),
    # the robot stops as for a missing source, and the log says which source and how old its data is.
    last_scan = probe.now_ns
    capfd.readouterr()  # only what follows counts
    probe.step_until(lambda: state() == (1, "invalid source"), "stop for a stale scan",
                     lambda: probe.command(0.3), ticks=60)
    assert probe.vx() == 0.0
    assert 2.0 < (probe.now_ns - last_scan) * 1e-9 <= 2.0 + 2 * TICK_NS * 1e-9
    err = capfd.readouterr().err
    assert re.search(r"\[scan\]: latest data is 2\.\d+ s old \(source_timeout 2\.0 s\)", err), err
    assert "Robot to stop due to invalid source (scan: latest data is" in err, err
    probe.step_until(lambda: state() == (0, "") and probe.vx() == 0.3, "normal operation with fresh scans",
                     send(None))

    # A stopped input: zeros for stop_pub_timeout (1 s) from the first zero, then silence.
    probe.step_until(lambda: probe.vx() == 0.0, "the input's zero",
                     functools.partial(probe.scan_and_command, None, 0.0))
    first_zero, count, mark = probe.now_ns, len(probe.outputs), probe.mark()
    for _ in range(40):  # 2 s of zero commands
        probe.tick()
        probe.scan_and_command(None, 0.0)
    probe.settle(mark, 40)
    zeros = len(probe.outputs) - count
    print(f"\n{zeros} zero commands published after the first one (stop_pub_timeout 1 s, 20 Hz input)")
    assert all(probe.vx(k) == 0.0 for k in range(count - len(probe.outputs), 0))
    assert 19 <= zeros <= 20  # 1 s of the 20 Hz input (the last one on the edge), not the 2 s sent
    assert probe.now_ns - first_zero == 40 * TICK_NS


@pytest.fixture
def cloud_rig(ros_context: Any) -> Iterator[tuple[Probe, Any]]:
    harness = None
    try:
        harness, probe, server = bring_up(ros_context, True, [
            Parameter("polygons", value=["PolygonStop", "FootprintApproach"]),
            Parameter("PolygonStop.type", value="polygon"),
            Parameter("PolygonStop.points", value="[[0.25, 0.3], [0.25, -0.3], [0.0, -0.3], [0.0, 0.3]]"),
            Parameter("PolygonStop.action_type", value="stop"),
            Parameter("PolygonStop.visualize", value=True),  # no polygon_pub_topic: on its own name
            Parameter("FootprintApproach.type", value="polygon"),
            Parameter("FootprintApproach.action_type", value="approach"),
            Parameter("FootprintApproach.min_points", value=6),
            Parameter("observation_sources", value=["cloud"]), Parameter("cloud.type", value="pointcloud"),
            Parameter("cloud.topic", value="points")])
        yield probe, server
    finally:
        if harness is not None:
            harness.close()


def test_a_point_cloud_drives_approach_and_stop_and_stamped_commands_keep_their_header(
        cloud_rig: tuple[Probe, Any]) -> None:
    probe, server = cloud_rig
    footprint = PolygonStamped()
    footprint.header.frame_id = "odom"
    footprint.polygon.points = [Point32(x=x, y=y) for x, y in ((0.2, 0.2), (0.2, -0.2), (-0.2, -0.2),
                                                                (-0.2, 0.2))]
    wait_until(lambda: probe.footprint_pub.get_subscription_count() > 0, 20.0, "footprint discovery")

    def send(x: float, z: float) -> Callable[[], None]:
        """Eight points across y at base (x, z), given in base_scan; then a 0.3 m/s command."""
        pts = [(x - SCAN_IN_BASE[0], -0.14 + 0.04 * i, z - SCAN_IN_BASE[2]) for i in range(8)]

        def go() -> None:
            probe.footprint_pub.publish(footprint)
            probe.cloud_pub.publish(cloud_msg(pts, "base_scan", _time(probe.now_ns)))
            probe.command(0.3)
        return go

    # Footprint front at 0.2, data at 0.6: contact after 0.4 m, 1.33 s; the 0.1 s simulation finds
    # it at step 14 and reports 1.3 s, so 0.3 m/s becomes 0.3 · 1.3 / 2.0 (time_before_collision).
    probe.step_until(lambda: probe.vx() == pytest.approx(0.195), "approach speed", send(0.6, 0.2))
    assert (probe.states[-1].action_type, probe.states[-1].polygon_name) == (3, "FootprintApproach")
    out = probe.outputs[-1]
    assert out.header.frame_id == "base_link"  # the input's frame and stamp, not the monitor's
    assert out.header.stamp.sec * 1_000_000_000 + out.header.stamp.nanosec == probe.now_ns - 7
    probe.step_until(lambda: probe.vx() == 0.3, "floor points ignored", send(0.22, 0.02))
    probe.step_until(lambda: probe.vx() == 0.0, "stop for points in the stop polygon", send(0.22, 0.2))
    assert (probe.states[-1].action_type, probe.states[-1].polygon_name) == (1, "PolygonStop")
    assert server.monitor.zones[1].outline is not None  # the footprint arrived through its topic
    probe.step_until(lambda: bool(probe.named_polygons), "the stop polygon on its own name", send(0.22, 0.2))
    assert [c for p in probe.named_polygons[-1].polygon.points for c in (p.x, p.y)] == pytest.approx(
        [0.25, 0.3, 0.25, -0.3, 0.0, -0.3, 0.0, 0.3])


@pytest.mark.parametrize(("params", "message"), [
    ([Parameter("PolygonStop.points", value="[[0.4, 0.3], [0.0, -0.3]]")],
     "points = '[[0.4, 0.3], [0.0, -0.3]]': a polygon needs at least 3 points, got 2"),
    ([Parameter("PolygonStop.points", value=[0.4, 0.3, 0.4, -0.3, 0.0, -0.3, 0.0, 0.3])],
     "Jazzy takes PolygonStop.points as a string"),
    ([Parameter("PolygonStop.action_type", value="brake")], "action_type = 'brake': must be one of"),
    ([Parameter("PolygonStop.type", value="velocity_polygon")], "type = 'velocity_polygon'"),
    ([Parameter("scan.topic", value="")], "topic = '': a source needs a topic"),
    ([Parameter("PolygonStop.sources_names", value=["lidar"])], "names lidar, not in observation_sources"),
])
def test_bad_parameters_fail_configure_naming_parameter_and_value(
        ros_context: Any, capfd: Any, params: list[Parameter], message: str) -> None:
    from rclpy.lifecycle import TransitionCallbackReturn

    base = [Parameter("polygons", value=["PolygonStop"]), Parameter("PolygonStop.type", value="polygon"),
            Parameter("PolygonStop.points", value=STOP_ZONE),
            Parameter("PolygonStop.action_type", value="stop"),
            Parameter("observation_sources", value=["scan"])]
    names = {p.name for p in params}
    node = CollisionMonitorNode(context=ros_context,
                                parameter_overrides=[p for p in base if p.name not in names] + params)
    try:
        assert node.trigger_configure() == TransitionCallbackReturn.FAILURE
        err = capfd.readouterr().err
        assert "collision_monitor" in err and message in err, err
    finally:
        node.destroy_node()


class BufferListener:
    """A TransformListener stand-in over a plain TransformBuffer (no DDS)."""

    def __init__(self) -> None:
        self.buffer = TransformBuffer()

    def lookup(self, target: str, source: str, time: float | None = None) -> Transform:
        return self.buffer.lookup(target, source, time)


def test_source_frames_correct_the_base_shift_through_odom_within_transform_tolerance() -> None:
    listener = BufferListener()
    listener.buffer.set_transform("base_footprint", "base_scan", 0.0, Transform(*SCAN_IN_BASE), static=True)
    for stamp, x in ((10.0, 1.0), (10.1, 1.05), (10.2, 1.1)):  # 0.5 m/s along odom x
        listener.buffer.set_transform("odom", "base_footprint", stamp, Transform.from_xy_yaw(x, 2.0, 0.0))
    obstacle = np.array([[0.5, 0.0, 0.0]])  # 0.5 m ahead of the sensor, seen at t = 10.0
    frames = SourceFrames(listener, "base_footprint", "odom", 0.1, True)  # type: ignore[arg-type]
    assert frames.sensor_to_base("base_scan", 10.0, 10.2).apply(obstacle)[0, 0] == pytest.approx(0.336)
    # now = 10.25: TF ends at 10.2, within transform_tolerance: the newest transform stands in
    assert frames.sensor_to_base("base_scan", 10.0, 10.25).apply(obstacle)[0, 0] == pytest.approx(0.336)
    with pytest.raises(TransformError):  # TF 0.3 s behind: the source is invalid
        frames.sensor_to_base("base_scan", 10.0, 10.5)
    uncorrected = SourceFrames(listener, "base_footprint", "odom", 0.1, False)  # type: ignore[arg-type]
    assert uncorrected.sensor_to_base("base_scan", 10.0, 10.2).apply(obstacle)[0, 0] == pytest.approx(0.436)
