"""amcl node against a fake parked robot: initial pose checks, map→odom, warnings, global localization,
the localization health it reports when scans return almost nothing, and beam skipping."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.srv")

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.srv import SetInitialPose
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Empty

from nav_stack.core.localization.health import LocalizationState, position_std
from nav_stack.core.localization.likelihood_field_prob import LikelihoodFieldProbModel
from nav_stack.ros.common.conversions import pose_from_2d
from nav_stack.ros.common.qos import DEFAULT, LATCHED
from nav_stack.ros.localization.amcl_messages import LOCALIZATION_STATUS, covariance_3x3
from nav_stack.ros.localization.amcl_node import NO_POSE_WARNING, AmclNode
from navsuite_testing.localization.nodes import call
from navsuite_testing.ros import spin_until
from ros_tools.tf.ros import TransformListener
from tests.helpers.nav_ros_loc_fakes import BEAMS, FakeRobot

pytestmark = pytest.mark.ros
TRUE_POSE = (-2.0, -0.5, 0.0)


class Graph:
    def __init__(self, context: Any, overrides: list[Parameter], given_rng: bool = True) -> None:
        """``given_rng`` False: the node makes its generator from its ``random_seed`` parameter."""
        rng = np.random.default_rng(0) if given_rng else None
        self.amcl = AmclNode(rng=rng, context=context, parameter_overrides=overrides)
        self.probe = Node("amcl_probe", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.amcl)
        self.executor.add_node(self.probe)
        self.robot = FakeRobot(self.probe, TRUE_POSE)
        self.poses: list[PoseWithCovarianceStamped] = []
        self.probe.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", self.poses.append, LATCHED)
        self.initial = self.probe.create_publisher(PoseWithCovarianceStamped, "/initialpose", DEFAULT)
        self.tf = TransformListener(self.probe)
        assert self.amcl.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert self.amcl.trigger_activate() == TransitionCallbackReturn.SUCCESS
        self.robot.publish_map()
        spin_until(self.executor, lambda: self.amcl.amcl is not None, 10.0, "AMCL to receive the map")

    def spin_until(self, predicate: Any, what: str, timeout: float = 15.0) -> None:
        spin_until(self.executor, predicate, timeout, what)

    def close(self) -> None:
        self.executor.shutdown()
        self.amcl.destroy_node()
        self.probe.destroy_node()


@pytest.fixture
def overrides() -> list[Parameter]:
    return []


@pytest.fixture
def graph(ros_context: Any, overrides: list[Parameter]) -> Iterator[Graph]:
    g = Graph(ros_context, overrides)
    try:
        yield g
    finally:
        g.close()


def _pose_msg(x: float, y: float, yaw: float, frame: str = "map") -> PoseWithCovarianceStamped:
    msg = PoseWithCovarianceStamped()
    msg.header.frame_id = frame
    msg.pose.pose = pose_from_2d(x, y, 0.0)
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    cov = [0.0] * 36
    cov[0] = cov[7] = 0.25
    cov[35] = 0.068
    msg.pose.covariance = cov
    return msg


class Log:
    """Accumulates what the process wrote to stderr (rcutils logs) through pytest's capfd."""

    def __init__(self, capfd: Any) -> None:
        self.capfd = capfd
        self.text = ""

    def has(self, fragment: str) -> bool:
        self.text += self.capfd.readouterr().err
        return fragment in self.text


def test_bad_initial_poses_are_rejected_and_a_good_one_localizes(graph: Graph, capfd: Any) -> None:
    log = Log(capfd)
    graph.initial.publish(_pose_msg(math.nan, -0.5, 0.0))
    graph.spin_until(lambda: log.has("position (nan, -0.5) is not finite"), "the NaN rejection")
    graph.initial.publish(_pose_msg(-2.0, -0.5, 0.0, frame="odom"))
    graph.spin_until(lambda: log.has('initial poses must be in the global frame, "map"'),
                     "the frame rejection")
    graph.initial.publish(_pose_msg(40.0, -0.5, 0.0))
    graph.spin_until(lambda: log.has("lies outside the map"), "the off-map rejection")
    assert not graph.amcl.amcl.initialized and not graph.poses

    request = SetInitialPose.Request(pose=_pose_msg(-1.8, -0.4, 0.1))  # a slightly wrong guess
    call(graph.executor, graph.probe.create_client(SetInitialPose, "/set_initial_pose"), request)
    graph.spin_until(lambda: bool(graph.poses), "amcl_pose after the initial pose")
    # Standing still, only no-motion updates refine the estimate: ask for a few.
    nomotion = graph.probe.create_client(Empty, "/request_nomotion_update")
    for _ in range(6):
        count = len(graph.poses)
        call(graph.executor, nomotion, Empty.Request())
        graph.spin_until(lambda c=count: len(graph.poses) > c, "a no-motion update")
    pose = graph.poses[-1].pose.pose
    assert math.hypot(pose.position.x - TRUE_POSE[0], pose.position.y - TRUE_POSE[1]) < 0.1
    graph.spin_until(lambda: graph.tf.buffer.can_transform("map", "odom"), "map→odom on /tf")
    map_odom = graph.tf.buffer.lookup("map", "odom")
    assert math.hypot(map_odom.x, map_odom.y) < 0.1 and abs(map_odom.yaw) < 0.1  # odom = map here


def test_no_initial_pose_warns_and_global_localization_spreads_particles(graph: Graph, capfd: Any) -> None:
    log = Log(capfd)
    graph.spin_until(lambda: log.has(NO_POSE_WARNING), "Nav2's 'set the initial pose' warning")
    assert not graph.poses
    reinitialize = graph.probe.create_client(Empty, "/reinitialize_global_localization")
    call(graph.executor, reinitialize, Empty.Request())
    filt = graph.amcl.amcl
    particles = filt.particles
    assert particles.shape[0] == filt.params.max_particles
    spec = filt.spec
    mx, my = spec.world_to_cell(particles[:, 0], particles[:, 1])
    assert np.all(graph.robot.map.data[my, mx] == 0)  # free space only
    assert particles[:, 0].std() > 1.0 and particles[:, 1].std() > 1.0 and particles[:, 2].std() > 1.5
    graph.spin_until(lambda: bool(graph.poses), "amcl_pose after the first update of the spread filter")


@pytest.mark.parametrize("overrides", [[Parameter("set_initial_pose", value=True),
                                        Parameter("initial_pose.x", value=-2.0),
                                        Parameter("initial_pose.y", value=-0.5)]])
def test_initial_pose_from_nav2_nested_parameters(graph: Graph) -> None:
    graph.spin_until(lambda: bool(graph.poses), "amcl_pose from the parameter initial pose")
    first = graph.poses[0].pose.pose.position
    assert (first.x, first.y) == pytest.approx((-2.0, -0.5), abs=0.1)
    graph.spin_until(lambda: graph.tf.buffer.can_transform("map", "base_footprint"), "map→base_footprint")


def test_random_seed_parameter_makes_the_filter_repeat(ros_context: Any) -> None:
    """Two filters configured with the same ``random_seed`` draw the same particles; -1 does not repeat."""
    def first_draws(seed: int) -> np.ndarray:
        node = AmclNode(context=ros_context, parameter_overrides=[Parameter("random_seed", value=seed)])
        try:
            assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
            return node.rng.random(8)
        finally:
            node.destroy_node()

    assert np.array_equal(first_draws(7), first_draws(7))
    assert not np.array_equal(first_draws(7), first_draws(8))
    assert not np.array_equal(first_draws(-1), first_draws(-1))


def test_each_initial_pose_draws_the_same_cloud_whatever_the_filter_drew_before(ros_context: Any) -> None:
    """``random_seed`` is applied again at every initial pose, so the cloud drawn there depends on the
    pose alone, not on how many scans the filter took before it (in a lockstep run, DDS timing)."""
    graph = Graph(ros_context, [Parameter("random_seed", value=3)], given_rng=False)
    try:
        client = graph.probe.create_client(SetInitialPose, "/set_initial_pose")
        clouds = []
        for draws_before in (0, 5):
            graph.amcl.rng.random(draws_before)  # what scan updates before the pose would have drawn
            call(graph.executor, client, SetInitialPose.Request(pose=_pose_msg(-1.8, -0.4, 0.1)))
            assert graph.amcl.amcl is not None
            clouds.append(graph.amcl.amcl.particles.copy())
        assert clouds[0].shape[0] > 0 and np.array_equal(clouds[0], clouds[1])
    finally:
        graph.close()


class Updates:
    """No-motion filter updates of a parked robot, each recorded as (returns, state) from amcl's monitor."""

    def __init__(self, graph: Graph) -> None:
        self.graph = graph
        self.nomotion = graph.probe.create_client(Empty, "/request_nomotion_update")

    def run(self, count: int) -> list[tuple[int, LocalizationState]]:
        trace = []
        for _ in range(count):
            seen = len(self.graph.poses)
            call(self.graph.executor, self.nomotion, Empty.Request())
            self.graph.spin_until(lambda s=seen: len(self.graph.poses) > s, "a no-motion update")
            monitor = self.graph.amcl.health.monitor
            trace.append((monitor.sample.returns, monitor.state))
        return trace


def test_scans_that_return_almost_nothing_degrade_localization_once_with_the_cause(graph: Graph,
                                                                                 capfd: Any) -> None:
    """A parked robot whose lidar suddenly sees only a 30° arc (open space): after 5 updates amcl warns
    once, naming the numbers, and reports WARN on /diagnostics; with walls back it recovers after 3."""
    log = Log(capfd)
    statuses: list[DiagnosticStatus] = []
    graph.probe.create_subscription(
        DiagnosticArray, "/diagnostics",
        lambda msg: statuses.extend(s for s in msg.status if s.name == LOCALIZATION_STATUS), DEFAULT)
    tight = _pose_msg(*TRUE_POSE)
    tight.pose.covariance = [0.01 if i in (0, 7) else 0.005 if i == 35 else 0.0 for i in range(36)]
    call(graph.executor, graph.probe.create_client(SetInitialPose, "/set_initial_pose"),
         SetInitialPose.Request(pose=tight))
    updates = Updates(graph)
    walls = graph.robot.ranges
    before = updates.run(3)
    assert all(state is LocalizationState.OK and r >= 50 for r, state in before), before
    sample = graph.amcl.health.monitor.sample
    assert position_std(covariance_3x3(graph.poses[-1].pose.covariance)) == pytest.approx(sample.position_std)

    open_space = np.full(BEAMS, np.inf)
    open_space[:30] = walls[:30]  # one 30° arc still sees a wall
    sub = open_space[::6]  # AMCL's 60 of 360 beams
    returns = int(np.count_nonzero((sub > 0.12) & (sub < 3.5)))
    graph.robot.ranges = open_space
    lost = updates.run(8)
    first = next(i for i, (r, _) in enumerate(lost) if r == returns)  # a scan in flight may come first
    assert first <= 2 and all(r == returns for r, _ in lost[first:]), lost
    assert [state for _, state in lost[first:first + 5]] == [LocalizationState.OK] * 4 + [
        LocalizationState.DEGRADED], lost
    cause = f"few beams on walls: {returns} of 60 beams returned within 3.5 m (< 20 %)"
    graph.spin_until(lambda: log.has(f"localization degraded: {cause}"), "the degradation warning")
    graph.spin_until(lambda: bool(statuses) and statuses[-1].level == DiagnosticStatus.WARN, "a WARN status")
    assert statuses[-1].message == cause
    assert {kv.key: kv.value for kv in statuses[-1].values}["valid beams"] == f"{returns} of 60 within 3.5 m"

    graph.robot.ranges = walls
    back = updates.run(6)
    first = next(i for i, (r, _) in enumerate(back) if r >= 50)
    assert [state for _, state in back[first:first + 3]] == [LocalizationState.DEGRADED] * 2 + [
        LocalizationState.OK], back
    graph.spin_until(lambda: log.has("localization recovered: "), "the recovery info")
    graph.spin_until(lambda: statuses[-1].level == DiagnosticStatus.OK, "an OK status")
    assert log.text.count("localization degraded:") == 1


def test_do_beamskip_is_said_to_have_no_effect_and_is_silent_when_off(ros_context: Any, capfd: Any) -> None:
    """Issue 49: a Nav2 parameter accepted and never read is said at startup, with its name."""
    def configure_with(do_beamskip: bool) -> str:
        overrides = [Parameter("do_beamskip", value=do_beamskip)]
        node = AmclNode(context=ros_context, parameter_overrides=overrides)
        try:
            capfd.readouterr()
            assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
            return str(capfd.readouterr().err)
        finally:
            node.destroy_node()

    said = configure_with(True)
    assert "do_beamskip is true but has no effect with laser_model_type 'likelihood_field'" in said, said
    assert "beam skipping only works with laser_model_type 'likelihood_field_prob'" in said, said
    assert "beam_skip_error_threshold are ignored" in said
    assert "do_beamskip" not in configure_with(False)


@pytest.mark.parametrize("overrides", [[Parameter("laser_model_type", value="likelihood_field_prob"),
                                        Parameter("do_beamskip", value=True)]])
def test_likelihood_field_prob_with_beam_skipping_localizes_past_an_unmapped_obstacle(graph: Graph,
                                                                                     capfd: Any) -> None:
    """Nav2's likelihood_field_prob: a person 0.4 m in front of the parked robot (not in the map) cuts
    7 of AMCL's 60 beams short; once the cloud converges those beams are skipped and the estimate
    from a slightly wrong initial pose still lands on the truth. No "has no effect" warning."""
    person = np.r_[0:21, 340:360]  # ±20° of the 360 beams, i.e. 7 of AMCL's 60 (step ceil(360 / 60) = 6)
    graph.robot.ranges[person] = 0.4
    guess = _pose_msg(-1.88, -0.42, 0.05)  # σ 0.1 m: the first resample leaves a converged cloud
    guess.pose.covariance = [0.01 if i in (0, 7) else 0.005 if i == 35 else 0.0 for i in range(36)]
    call(graph.executor, graph.probe.create_client(SetInitialPose, "/set_initial_pose"),
         SetInitialPose.Request(pose=guess))
    filt = graph.amcl.amcl
    assert filt is not None and isinstance(filt.model, LikelihoodFieldProbModel)
    Updates(graph).run(8)
    weights = filt.last_scan_weights
    assert weights is not None and weights.skipping and not weights.too_many_skipped
    assert weights.skipped_count >= 5, weights.skipped_count
    pose = graph.poses[-1].pose.pose
    assert math.hypot(pose.position.x - TRUE_POSE[0], pose.position.y - TRUE_POSE[1]) < 0.1
    assert "do_beamskip" not in capfd.readouterr().err
