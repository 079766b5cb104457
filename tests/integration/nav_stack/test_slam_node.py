"""The slam node in-process with a fake robot (analytic hexagon room): map, pose, TF, pause, save_map,
and slam_toolbox's Pause / serialize_map / deserialize_map refusing what they cannot do.

The fake robot publishes TF and a scan per step on a fake timeline (navsuite_testing/slam/fakes.py);
each step waits for the node's ``slam/pose`` of that stamp, so no scan is dropped by the node's
one-slot mailbox and the run is deterministic.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.parameter import Parameter
from slam_toolbox.srv import DeserializePoseGraph, Pause, SerializePoseGraph
from std_srvs.srv import SetBool

from nav_stack.core.costmap.observation import LaserScan
from nav_stack.core.geometry import Pose2D
from nav_stack.core.map_io import load_map
from nav_stack.core.slam import GraphFileError, GridSlam, read_graph
from nav_stack.ros.common.conversions import grid_from_occupancy
from nav_stack.ros.slam.slam_node import SlamNode
from navsuite_testing.nav.world import Harness
from navsuite_testing.ros import wait_until
from navsuite_testing.slam.fakes import LASER_X, START, TRUTH_SPEC, FakeRobot, tour
from navsuite_testing.slam.node_probe import Probe, drive
from navsuite_testing.slam.world import iou_dilated, resample_to
from ros_tools.tf import Transform
from ros_tools.tf.ros import stamp_to_seconds, transform_from_msg, transform_to_msg

pytestmark = pytest.mark.ros


@pytest.fixture
def rig(ros_context: Any) -> Any:
    harness = Harness(ros_context)
    overrides = [Parameter("map_start_pose", value=list(START)), Parameter("map_update_interval", value=1.0)]
    slam = SlamNode(context=ros_context, parameter_overrides=overrides)
    robot, probe = FakeRobot(context=ros_context), Probe(context=ros_context)
    try:
        harness.add(slam, robot, probe)
        harness.bring_up(slam)
        yield slam, robot, probe
    finally:
        harness.close()


class Settled:
    """True once ``value()`` is positive and has not changed for ``quiet`` s (wall)."""

    def __init__(self, value: Any, quiet: float = 1.0) -> None:
        self.value, self.quiet = value, quiet
        self.last, self.since = value(), time.monotonic()

    def __call__(self) -> bool:
        now = self.value()
        if now != self.last:
            self.last, self.since = now, time.monotonic()
        return now > 0 and time.monotonic() - self.since >= self.quiet


def known_cells(msg: OccupancyGrid) -> int:
    return int((grid_from_occupancy(msg)[0] >= 0).sum())


def test_map_grows_matches_the_room_and_tracks_the_pose(rig: Any) -> None:
    slam, robot, probe = rig
    path = tour(robot.world)
    drive(robot, probe, path, slam)
    wait_until(lambda: len(probe.maps) >= 3, 10.0, "three /map messages")
    assert known_cells(probe.maps[0]) < known_cells(probe.maps[-1]), "the map did not grow"
    data, spec = grid_from_occupancy(probe.maps[-1])
    assert probe.maps[-1].header.frame_id == "map"
    estimate = resample_to(data >= 65, spec, TRUTH_SPEC, False)
    truth = robot.world.occupied_mask(TRUTH_SPEC)
    iou = iou_dilated(estimate, truth)
    assert iou >= 0.8, f"occupied IoU {iou:.3f}"
    last = probe.poses[-1].pose.pose.position
    error = math.hypot(last.x - path[-1].x, last.y - path[-1].y)
    assert error <= 0.1, f"final pose error {error:.3f} m"
    correction = slam.tf.lookup("map", "odom")
    assert math.hypot(correction.x - START.x, correction.y - START.y) <= 0.1


def test_pause_ignores_scans_until_resumed(rig: Any) -> None:
    slam, robot, probe = rig
    path = tour(robot.world)
    drive(robot, probe, path[:5], slam)
    assert probe.call(probe.pause, SetBool.Request(data=True)).success
    paused_from = robot.time
    for pose in path[5:30]:
        robot.step(pose)
    settled = Settled(lambda: slam.ignored_scans)  # the paused scans reach the node (best effort)
    wait_until(settled, 10.0, "the scans sent while paused to arrive")
    assert probe.call(probe.pause, SetBool.Request(data=False)).success
    resumed_at = robot.time
    drive(robot, probe, path[30:32], slam)
    ignored = [s for s in probe.stamps() if paused_from < s <= resumed_at]
    assert ignored == [], f"poses published while paused: {ignored}"
    assert slam.slam is not None and len(slam.slam.poses) >= 2


def test_a_scan_sent_before_its_odometry_waits_for_it(rig: Any) -> None:
    """Each scan goes out before the odometry TF at its stamp: the node parks it, retries when the TF
    arrives, drops none, and maps exactly what the pure core maps from the same inputs in order."""
    slam, robot, probe = rig
    for pose in tour(robot.world)[:30]:
        t = robot.step(pose, scan_first=True)
        wait_until(lambda t=t: any(abs(s - t) < 1e-6 for s in probe.stamps()[-3:]), 10.0,
                   f"slam/pose of the scan at {t:.1f} s")
    assert slam.parked_scans > 0, "no scan arrived before its odometry: the test did not test waiting"
    assert slam.dropped_scans == 0
    core = GridSlam(slam.params)
    for odom, msg in robot.sent:
        seen = transform_from_msg(transform_to_msg(Transform.from_xy_yaw(*odom), "odom", "base_footprint",
                                                   msg.header.stamp))  # what the node reads from TF
        scan = LaserScan(np.asarray(msg.ranges, dtype=np.float64), msg.angle_min, msg.angle_increment,
                         msg.range_min, msg.range_max)
        core.process(scan, Pose2D(seen.x, seen.y, seen.yaw), stamp_to_seconds(msg.header.stamp),
                     Pose2D(LASER_X, 0.0, 0.0))
    assert slam.slam is not None
    np.testing.assert_allclose(slam.slam.poses, core.poses, atol=1e-9)


def test_save_map_writes_a_map_that_map_io_loads(rig: Any, tmp_path: Path) -> None:
    slam, robot, probe = rig
    refused = probe.call(probe.save, SaveMap.Request(map_url=str(tmp_path / "early")))
    assert not refused.result, "saved a map before any scan"
    drive(robot, probe, tour(robot.world)[:25], slam)
    png = probe.call(probe.save, SaveMap.Request(map_url=str(tmp_path / "m"), image_format="png"))
    assert not png.result and not (tmp_path / "m.yaml").exists()
    assert probe.call(probe.save, SaveMap.Request(map_url=str(tmp_path / "m"))).result
    loaded = load_map(tmp_path / "m.yaml")
    data, spec = slam.slam.occupancy()
    assert loaded.spec == spec
    np.testing.assert_array_equal(loaded.data, data)
    assert (loaded.data == 100).sum() > 100 and (loaded.data == 0).sum() > 1000


def test_pause_toggles_and_bad_requests_leave_the_node_serving(rig: Any, tmp_path: Path) -> None:
    slam, robot, probe = rig
    pause = probe.create_client(Pause, "/slam_toolbox/pause_new_measurements")
    serialize = probe.create_client(SerializePoseGraph, "/slam_toolbox/serialize_map")
    deserialize = probe.create_client(DeserializePoseGraph, "/slam_toolbox/deserialize_map")
    assert probe.call(pause, Pause.Request()).status and slam.paused
    assert probe.call(pause, Pause.Request()).status and not slam.paused

    # No scan yet: nothing to write.
    failed = SerializePoseGraph.Response.RESULT_FAILED_TO_WRITE_FILE
    assert probe.call(serialize, SerializePoseGraph.Request(filename=str(tmp_path / "a"))).result == failed

    drive(robot, probe, tour(robot.world)[:30], slam)
    nodes = len(slam.slam.poses)
    assert nodes >= 3
    base = tmp_path / "room"
    ok = SerializePoseGraph.Response.RESULT_SUCCESS
    assert probe.call(serialize, SerializePoseGraph.Request(filename=str(base))).result == ok
    unwritable = SerializePoseGraph.Request(filename=str(tmp_path / "no" / "dir"))
    assert probe.call(serialize, unwritable).result == failed
    for request in (
        DeserializePoseGraph.Request(filename=str(base), match_type=DeserializePoseGraph.Request.UNSET),
        DeserializePoseGraph.Request(filename=str(tmp_path / "missing"), match_type=1),
    ):
        probe.call(deserialize, request)
        assert len(slam.slam.poses) == nodes, "a refused deserialize replaced the session"
    # A good one replaces the session and publishes its map at once.
    maps = len(probe.maps)
    probe.call(deserialize, DeserializePoseGraph.Request(
        filename=str(base), match_type=DeserializePoseGraph.Request.LOCALIZE_AT_POSE))
    wait_until(lambda: len(probe.maps) > maps, 10.0, "the loaded map")
    assert type(slam.slam).__name__ == "GraphLocalizer" and len(read_graph(base).poses) == nodes


def test_a_graph_that_cannot_be_loaded_fails_configure_naming_it(ros_context: Any, tmp_path: Path) -> None:
    missing = tmp_path / "missing"
    slam = SlamNode(context=ros_context, parameter_overrides=[
        Parameter("mode", value="localization"), Parameter("map_file_name", value=str(missing))])
    try:
        with pytest.raises(GraphFileError, match=r"missing\.posegraph"):
            slam.configure()
    finally:
        slam.destroy_node()


def test_localization_without_a_graph_is_refused_naming_the_parameter(ros_context: Any) -> None:
    slam = SlamNode(context=ros_context, parameter_overrides=[Parameter("mode", value="localization")])
    try:
        with pytest.raises(ValueError, match="map_file_name"):
            slam.configure()
    finally:
        slam.destroy_node()
