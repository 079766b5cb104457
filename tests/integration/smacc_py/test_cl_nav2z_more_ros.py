"""The cl_nav2z pieces of issue 21 item 2 on the real runtime (use_sim_time, FakeNav2's /clock and TF):
named waypoints, CbRetry, CbRotateLookAt, CbWaitTransform, the waypoints visualizer's latched markers,
CbPauseSlam/CbResumeSlam against nav_stack's SLAM node, and CpCostmapSwitch against nav_stack's costmap
node. Every wait polls a condition with a deadline; durations are compared on sim time only."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from nav_stack.ros.costmap.costmap_ros import CostmapROS
from nav_stack.ros.slam.slam_node import SlamNode
from navsuite_testing.nav.world import Harness
from navsuite_testing.ros import spin_until, wait_until
from smacc_py.clients.cl_nav2z import (
    CbNavigateGlobalPosition,
    CbNavigateNamedWaypoint,
    CbPauseSlam,
    CbResumeSlam,
    CbRetry,
    CbRotateLookAt,
    CbSeekWaypoint,
    CbWaitPose,
    CbWaitTransform,
    CpCostmapSwitch,
    StandardLayers,
)
from smacc_py.clients.cl_nav2z.cp_waypoints_visualizer import LATCHED_QOS, MARKERS_TOPIC, REACHED
from smacc_py.core import SmaccClientBehavior
from tests.helpers.smacc_nav2z_more_fakes import WAYPOINTS, add_until_reached, chain
from tests.helpers.smacc_ros_fake_nav2 import START_S
from tests.integration.smacc_py.conftest import transition_keys

pytestmark = pytest.mark.ros

MISSING_FRAME_TIMEOUT_S = 3.0  # sim s
#: sim s a wait for TF may take: /tf's discovery takes wall time, 6 wall s at the fake's 10x clock.
DISCOVERY_TIMEOUT_S = 60.0
N = TypeVar("N", bound=Node)


def _leaf(runtime: Any) -> str:
    names = runtime.sm.current_state_names()
    return names[-1] if names else ""


def _finish(runtime: Any, timeout: float = 30.0) -> str:
    wait_until(lambda: _leaf(runtime) in ("StDone", "StFailed"), timeout, "the machine to finish")
    return _leaf(runtime)


# ------------------------------------------------------------------ waypoints by name + visualizer
SEEK_B_THEN_A = [(CbSeekWaypoint, ("b",), {}), (CbNavigateNamedWaypoint, ("a",), {})]
SmNamedWaypoints = chain("SmNamedWaypoints", SEEK_B_THEN_A, last_target="StUntil")
add_until_reached(SmNamedWaypoints, "StUntil", "c")


def _goal_xy(goal: Any) -> tuple[float, float]:
    return goal.pose.pose.position.x, goal.pose.pose.position.y


def test_named_waypoints_and_their_latched_markers(stack: Any, ros_context: Any) -> None:
    fake, runtime = stack(SmNamedWaypoints)
    assert _finish(runtime) == "StDone"
    # seek b (no motion), navigate to a by name, then b and c until c is reached
    assert [_goal_xy(g) for g in fake.logs["navigate_to_pose"].goals] == [(1.0, 0.0), (2.0, 0.5), (2.0, 1.5)]
    assert transition_keys(runtime) == [("St0", "St1", "SUCCESS"), ("St1", "StUntil", "SUCCESS"),
                                        ("StUntil", "StUntil", "SUCCESS"), ("StUntil", "StDone", "SUCCESS")]
    assert runtime.sm.transition_log[-1].event.name == "c"
    probe = rclpy.create_node("markers_probe", context=ros_context)  # joins late: the topic is latched
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    received: list[MarkerArray] = []
    probe.create_subscription(MarkerArray, f"/{MARKERS_TOPIC}", received.append, LATCHED_QOS)
    try:
        spin_until(executor, lambda: any(all(m.color == REACHED for m in msg.markers) for msg in received),
                   15.0, "markers showing every waypoint reached")
        last = received[-1].markers
        assert [m.text for m in last if m.ns == "waypoints_labels"] == ["a", "b", "c"]
        assert [(m.pose.position.x, m.pose.position.y) for m in last if m.ns == "waypoints"] == [
            (w.x, w.y) for w in WAYPOINTS]
    finally:
        executor.shutdown()
        probe.destroy_node()


# ------------------------------------------------------------------ CbRetry
def test_retry_sends_a_fresh_goal_after_an_abort(stack: Any) -> None:
    sm = chain("SmRetry", [(CbRetry, (CbNavigateGlobalPosition, 1.0, 0.0), {"retries": 2})])
    fake, runtime = stack(sm, scripts={"navigate_to_pose": ["aborted", "succeeded"]})
    assert _finish(runtime) == "StDone"
    assert fake.logs["navigate_to_pose"].results == ["aborted", "succeeded"]
    assert [_goal_xy(g) for g in fake.logs["navigate_to_pose"].goals] == [(1.0, 0.0), (1.0, 0.0)]
    assert runtime.sm.transition_log[-1].event.attempts == 2


# ------------------------------------------------------------------ CbRotateLookAt, CbWaitTransform
def test_rotate_look_at_spins_toward_the_point(stack: Any) -> None:
    wait_pose = (CbWaitPose, (), {"timeout_s": DISCOVERY_TIMEOUT_S})
    sm = chain("SmLookAt", [wait_pose, (CbRotateLookAt, (0.0, 2.0), {})])
    fake, runtime = stack(sm)
    assert _finish(runtime) == "StDone"
    assert [g.target_yaw for g in fake.logs["spin"].goals] == [pytest.approx(math.pi / 2, abs=1e-3)]


def test_wait_transform_succeeds_on_fake_tf_and_fails_on_a_missing_frame(stack: Any) -> None:
    sm = chain("SmTf", [(CbWaitTransform, ("map", "base_link"), {"timeout_s": DISCOVERY_TIMEOUT_S}),
                        (CbWaitTransform, ("map", "gripper"), {"timeout_s": MISSING_FRAME_TIMEOUT_S})])
    _fake, runtime = stack(sm)
    assert _finish(runtime) == "StFailed"
    found, missing = runtime.sm.transition_log
    assert found.key() == ("St0", "St1", "SUCCESS")
    assert found.event.transform.x == pytest.approx(0.0, abs=1e-6)  # the fake robot stands at the origin
    assert missing.key() == ("St1", "StFailed", "ABORT")
    assert missing.stamp_s - found.stamp_s >= MISSING_FRAME_TIMEOUT_S  # on sim time
    assert missing.stamp_s > START_S
    assert "CbWaitTransform: no transform map <- gripper within 3.0 s" in missing.event.reason


# ------------------------------------------------------------------ SLAM pause / resume
@pytest.fixture
def configured(ros_context: Any) -> Iterator[Callable[[N], N]]:
    """``configured(node)``: a nav_stack lifecycle node, configured (its services and parameters exist
    from then on) and spun in the background until the test ends."""
    harness = Harness(ros_context)

    def configure(node: N) -> N:
        harness.add(node)
        assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS  # type: ignore[attr-defined]
        return node

    try:
        yield configure
    finally:
        harness.close()


def test_pause_and_resume_slam_switch_the_slam_node(stack: Any, configured: Any, ros_context: Any) -> None:
    slam = configured(SlamNode(context=ros_context))
    _fake, runtime = stack(chain("SmPauseResume", [(CbPauseSlam, (), {}), (CbResumeSlam, (), {})]))
    assert _finish(runtime) == "StDone"
    paused, resumed = runtime.sm.transition_log
    # The messages are the SLAM node's answers, which it gives after switching.
    assert (paused.key(), paused.event.message) == (("St0", "St1", "SUCCESS"), "new measurements paused")
    assert resumed.key() == ("St1", "StDone", "SUCCESS")
    assert resumed.event.message == "new measurements resumed"
    assert not slam.paused


# ------------------------------------------------------------------ CpCostmapSwitch
class CbDisableGlobalObstacles(SmaccClientBehavior):
    """Test behavior: disables the global obstacle layer and reports the answer."""

    def on_entry(self) -> None:
        switch = self.requires_component(CpCostmapSwitch)
        switch.disable(StandardLayers.GLOBAL_OBSTACLES_LAYER, self._answered)

    def _answered(self, succeeded: bool, detail: str) -> None:
        if succeeded:
            self.post_success_event()
        else:
            self.post_failure_event(reason=detail)


def test_costmap_switch_turns_the_layer_off_on_the_costmap_node(
    stack: Any, configured: Any, ros_context: Any
) -> None:
    # Nav2's layout, which CpCostmapSwitch addresses: the node /global_costmap/global_costmap.
    global_costmap = configured(CostmapROS("global_costmap", context=ros_context))
    assert global_costmap.get_parameter("obstacle_layer.enabled").value is True
    _fake, runtime = stack(chain("SmCostmap", [(CbDisableGlobalObstacles, (), {})]))
    assert _finish(runtime) == "StDone", runtime.sm.transition_log[-1].event
    assert global_costmap.get_parameter("obstacle_layer.enabled").value is False
    assert runtime.sm.requires_component(CpCostmapSwitch).enabled == {"global_costmap/obstacle_layer": False}
    layers = {layer.name: layer.enabled for layer in global_costmap.costmap.layers}
    assert layers == {"static_layer": True, "obstacle_layer": False, "inflation_layer": True}
