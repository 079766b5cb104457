"""A TurtleBot4 tours the depot: ``nav-bringup --robot tb4 --world depot_large`` reaches five goals in a row,
and two on Nav2 Jazzy's own nav2_params.yaml, unmodified (``--params config/jazzy/nav2_params.yaml``).

The round Create 3 base with its RPLIDAR A1 (12 m, in rplidar_link, turned +90° on the shell) runs on
config/nav2_params_tb4.yaml in the 30 m x 15 m depot: a hall with pillars and rooms behind 1 m doors.
The goals are the world's own spawn poses (room centres facing their doors, each checked free by
sim2d), visited north, south, south, north, north from the west end, so that every leg passes doors.

Each goal must succeed and leave the robot truly (sim2d's ground truth) within the goal checker's
reach of it, AMCL's estimate must follow the truth all along (the scan, its frame and its mount agree
between sim2d and TF), and the tour must not touch an obstacle. The final heading is judged by the
goal checker on AMCL's estimate; the truth's is not compared with the goal, because the robot still
turns after the goal checker's yes (it brakes from up to 1.8 rad/s, as a waffle does).

Determinism: the stack and this client are lockstep participants; the client holds the simulator
while each goal request crosses DDS, so the outcome depends on sim time only. Every wall-clock
timeout below is a safety net, never a measurement.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
import yaml

pytest.importorskip("nav_stack.ros.bringup.nav_bringup", reason="the stack does not exist yet")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.action import NavigateToPose
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan
from std_msgs.msg import UInt32

from nav_stack.ros.common.conversions import pose_stamped
from navsuite_testing.ros import REPO, BackgroundSpin
from ros_tools.runtime.actions import ActionClient, send_until_acknowledged
from ros_tools.runtime.lockstep import LockstepParticipant
from ros_tools.tf.ros import TransformListener
from tests.helpers.nav_ros_bt_stack import READY, Bringup, wait, yaw_of

pytestmark = [pytest.mark.slow, pytest.mark.ros]

WORLD = "depot_large"
SPAWNS: list[list[float]] = yaml.safe_load((REPO / "sim2d" / "worlds" / f"{WORLD}.yaml").read_text())[
    "spawns"]
#: Indices into the world's spawns: north room 1, south room 1, south room 3, north room 4, north
#: room 5; legs of about 6, 12, 12, 14 and 8 m, each through one or two doors.
TOUR = (1, 10, 12, 4, 5)
#: m: the goal checker's 0.25 (config/nav2_params_tb4.yaml) on AMCL's estimate, plus AMCL's error.
XY_TOLERANCE = 0.25 + 0.1
#: m and rad: AMCL's estimate against the truth at its stamp over the whole tour, RMS (a lidar mount
#: that sim2d and TF disagree on biases every estimate) and worst (bench/RESULTS.md: a waffle tracks
#: turtlebot3_world within 0.04 m and 0.025 rad RMS, 0.09 m at worst).
AMCL_RMS_XY, AMCL_RMS_YAW = 0.08, 0.05
AMCL_WORST_XY, AMCL_WORST_YAW = 0.25, 0.2
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
LEG_WALL_S = 300.0  # safety net per goal (wall s); a leg takes about a minute of sim time


def _seconds(stamp: Any) -> float:
    return float(stamp.sec) + stamp.nanosec * 1e-9


#: Parameter files → (nav-bringup's arguments, the spawns toured). The TurtleBot4's own file
#: (nav-bringup's default for tb4) tours all five; Nav2 Jazzy's own nav2_params.yaml, unmodified
#: (MPPI, the smoother, the velocity smoother and the collision monitor), the first two, about 80 s of
#: sim time: on a busy machine the Jazzy stack took 244 wall s for 130 sim s, the tb4 file 99 for 206
#: (a fresh-clone run, 2026-11-29), and all five legs cost 60 s of wall time idle
#: (they pass too: 0.02-0.07 m from each spawn, AMCL RMS 0.038 m, 2026-11-29).
PARAMS = {"tb4_params": ([], TOUR),
          "nav2_jazzy_params": (["--params", str(REPO / "config" / "jazzy" / "nav2_params.yaml")], TOUR[:2])}


@pytest.fixture(params=list(PARAMS))
def tb4_stack(request: pytest.FixtureRequest) -> Any:
    args, tour = PARAMS[request.param]
    stack = Bringup("--robot", "tb4", "--world", WORLD, *args)
    try:
        stack.wait_for_line(READY, timeout=240.0)
        yield stack, tour
    finally:
        code = stack.stop()
        assert code in (0, 130), f"nav-bringup ended with {code}:\n{stack.output()}"


class Observer:
    """The client's view: true and estimated poses (sim time s, x, y, yaw), first scan, collisions."""

    def __init__(self, node: Node) -> None:
        self.truths: list[tuple[float, float, float, float]] = []
        self.estimates: list[tuple[float, float, float, float]] = []
        self.scan: LaserScan | None = None
        self.collisions: int | None = None
        node.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", self._on_estimate, LATCHED)
        node.create_subscription(LaserScan, "/scan", self._on_scan, 1)
        node.create_subscription(UInt32, "/sim2d/collision_count", self._on_collisions, LATCHED)

    @staticmethod
    def _pose(stamp: Any, pose: Any) -> tuple[float, float, float, float]:
        return (_seconds(stamp), pose.position.x, pose.position.y, yaw_of(pose.orientation))

    def _on_truth(self, msg: Odometry) -> None:
        self.truths.append(self._pose(msg.header.stamp, msg.pose.pose))

    def _on_estimate(self, msg: PoseWithCovarianceStamped) -> None:
        self.estimates.append(self._pose(msg.header.stamp, msg.pose.pose))

    def _on_scan(self, msg: LaserScan) -> None:
        self.scan = self.scan or msg

    def _on_collisions(self, msg: UInt32) -> None:
        self.collisions = msg.data

    def describe_worst(self, xy: np.ndarray, heading: np.ndarray) -> str:
        """Where the worst estimate was: its sim time, the truth's turn rate there and the errors of
        the estimates around it (a failure message that says whether it was one outlier)."""
        worst = int(np.argmax(heading)) if heading.max() >= AMCL_WORST_YAW else int(np.argmax(xy))
        truths, stamp = np.array(self.truths), self.estimates[worst][0]
        rate = np.gradient(np.unwrap(truths[:, 3]), truths[:, 0])
        around = slice(max(0, worst - 3), worst + 4)
        return (f"worst estimate at t={stamp:.3f} s (estimate {worst} of {len(xy)}), truth turning at "
                f"{float(np.interp(stamp, truths[:, 0], rate)):.2f} rad/s; errors around it: "
                f"{np.round(xy[around], 3).tolist()} m, {np.round(heading[around], 3).tolist()} rad; "
                f"stamps {[round(e[0], 3) for e in self.estimates[around]]}")

    def localization_errors(self) -> tuple[np.ndarray, np.ndarray]:
        """Each estimate's distance (m) and heading difference (rad) from the truth at its stamp
        (interpolated between the 30 Hz truths)."""
        truths, estimates = np.array(self.truths), np.array(self.estimates)
        stamps = estimates[:, 0]
        x, y = (np.interp(stamps, truths[:, 0], truths[:, i]) for i in (1, 2))
        yaw = np.interp(stamps, truths[:, 0], np.unwrap(truths[:, 3]))
        heading = np.abs(np.remainder(estimates[:, 3] - yaw + math.pi, math.tau) - math.pi)
        return np.hypot(estimates[:, 1] - x, estimates[:, 2] - y), heading


def _navigate(client: ActionClient, lockstep: LockstepParticipant, x: float, y: float,
              yaw: float) -> tuple[Any, float]:
    """NavigateToPose to (x, y, yaw) in map: the result response and the sim time it took, as
    bt_navigator counts it in its feedback (s)."""
    goal = NavigateToPose.Goal(pose=pose_stamped(x, y, yaw, "map", Time()))
    copies: list[Any] = []
    lockstep.hold(lambda: any(future.done() for future, _ in copies), 4.0)
    navigation_times = [0.0]
    handle = send_until_acknowledged(
        client, goal, 30.0, copies=copies,
        feedback_callback=lambda m: navigation_times.append(_seconds(m.feedback.navigation_time)),
    ).result()
    assert handle.accepted, f"goal ({x}, {y}) rejected"
    result = handle.get_result_async()
    wait(result.done, LEG_WALL_S, f"the result of the goal ({x}, {y})")
    return result.result(), max(navigation_times)


@pytest.mark.timeout(1200)  # safety net: bringup, then five legs of LEG_WALL_S at most
def test_tb4_tours_the_depot(tb4_stack: tuple[Bringup, tuple[int, ...]], ros_context: Any) -> None:
    _stack, tour = tb4_stack
    node = Node("tb4_tour_client", context=ros_context)
    observer = Observer(node)
    client = ActionClient(node, NavigateToPose, "navigate_to_pose")
    lockstep = LockstepParticipant(node, "tb4_tour_client")
    # Made before the executor spins and destroyed with the node: destroying a subscription while
    # another thread builds its wait set kills that thread (rclpy's InvalidHandle, "cannot use
    # Destroyable"), and the goals' acknowledgements then go unheard (seen in a loop of this test).
    tf = TransformListener(node)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    spin = BackgroundSpin(executor)
    try:
        wait(client.server_is_ready, 60.0, "navigate_to_pose")
        wait(lambda: lockstep.reported_ns > 0 and observer.scan is not None and bool(observer.truths),
             30.0, "a first lockstep report, scan and ground truth")
        assert observer.scan is not None
        assert observer.scan.header.frame_id == "rplidar_link"
        assert observer.scan.range_max == pytest.approx(12.0)
        # AMCL's first map -> odom is stamped a transform_tolerance (1 s of sim time) after its scan, so
        # bt_navigator refuses a goal (TF_ERROR) until odometry has caught up with it: wait, as
        # BasicNavigator waits for /amcl_pose (tests/system/test_nav2_client_compat.py).
        tf.wait_for("map", "base_link", timeout=60.0)
        for index in tour:
            x, y, yaw = SPAWNS[index]
            response, took = _navigate(client, lockstep, x, y, yaw)
            assert response.status == GoalStatus.STATUS_SUCCEEDED, \
                f"spawn {index} ({x}, {y}): {response.result.error_code} {response.result.error_msg}"
            seen = len(observer.truths)
            wait(lambda seen=seen: len(observer.truths) > seen, 30.0, "a ground-truth pose after the result")
            _, tx, ty, _ = observer.truths[-1]
            off = math.hypot(tx - x, ty - y)
            print(f"spawn {index} ({x}, {y}): reached in {took:.1f} s of sim time, {off:.3f} m from it")
            assert off < XY_TOLERANCE, f"spawn {index}: the robot is truly at ({tx:.3f}, {ty:.3f})"
        xy, heading = observer.localization_errors()
        rms_xy, rms_yaw = (float(np.sqrt(np.mean(e * e))) for e in (xy, heading))
        print(f"AMCL: {len(xy)} estimates, RMS {rms_xy:.3f} m and {rms_yaw:.3f} rad, worst "
              f"{xy.max():.3f} m and {heading.max():.3f} rad")
        assert len(xy) > 20 and rms_xy < AMCL_RMS_XY and rms_yaw < AMCL_RMS_YAW
        assert xy.max() < AMCL_WORST_XY and heading.max() < AMCL_WORST_YAW, \
            observer.describe_worst(xy, heading)
        wait(lambda: observer.collisions is not None, 10.0, "/sim2d/collision_count")
        assert observer.collisions == 0, f"{observer.collisions} collisions on the tour"
    finally:
        spin.stop()  # first: nothing may be destroyed under a spinning thread
        lockstep.destroy()
        tf.destroy()
        node.destroy_node()
