"""The cl_nav2z pieces of issue 21 item 2 on the scripted world (smacc_nav2z_more_fakes.MoreNav2): named
waypoints, CbRetry, CbRotateLookAt, CbWaitTransform, CbPauseSlam/CbResumeSlam with CpSlamToolbox,
CpCostmapSwitch, the waypoint event dispatcher and the waypoints visualizer. Times are machine-clock s."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from ros_tools.tf import Transform
from smacc_py.clients.cl_nav2z import (
    CbNavigateForward,
    CbNavigateNamedWaypoint,
    CbNavigateNextWaypoint,
    CbNavigateNextWaypointUntilReached,
    CbPauseSlam,
    CbResumeSlam,
    CbRetry,
    CbRotateLookAt,
    CbSeekWaypoint,
    CbWaitTransform,
    ClNav2Z,
    CpCostmapSwitch,
    CpSlamToolbox,
    CpWaypointNavigator,
    CpWaypointsVisualizer,
    SlamToolboxState,
    StandardLayers,
    Waypoint,
    WaypointEventDispatcher,
)
from smacc_py.clients.cl_nav2z.client import SPIN
from smacc_py.clients.cl_nav2z.cp_waypoints_visualizer import PENDING, REACHED
from smacc_py.core import (
    EvCbSuccess,
    EvGoalWaypointReached,
    EvWaypoint,
    EvWaypointFinal,
    SmaccEvent,
    SmaccObserver,
    SmaccStateMachineBase,
    waypoint_event,
)
from tests.helpers.smacc_fake_nav import Nav2Script, RecordingPublisher
from tests.helpers.smacc_nav2z_more_fakes import MoreNav2, OrNav, add_until_reached, chain


def machine(behavior: type, *args: Any, **kwargs: Any) -> type[SmaccStateMachineBase]:
    """A machine whose St0 runs ``behavior(*args, **kwargs)``: success → StDone, failure → StFailed."""
    return chain(f"Sm{behavior.__name__}", [(behavior, args, kwargs)])


class Posted(SmaccObserver):
    """Every event posted to the machine."""

    def __init__(self) -> None:
        self.events: list[SmaccEvent] = []

    def on_event_posted(self, sm: Any, event: SmaccEvent) -> None:
        self.events.append(event)

    def of(self, event_type: type[SmaccEvent]) -> list[SmaccEvent]:
        return [e for e in self.events if isinstance(e, event_type)]


@pytest.fixture
def world() -> Iterator[Callable[..., MoreNav2]]:
    made: list[MoreNav2] = []

    def make(**script: Any) -> MoreNav2:
        made.append(MoreNav2(Nav2Script(**script)))
        return made[-1]

    yield make
    for each in made:
        each.close()


def run(
    nav2: MoreNav2, sm_type: type[SmaccStateMachineBase], max_sim_s: float = 60.0
) -> tuple[SmaccStateMachineBase, Posted]:
    """Start ``sm_type`` and drive it until it reaches StDone or StFailed."""
    posted = Posted()
    sm = nav2.start(sm_type)
    sm.add_observer(posted)
    assert nav2.drive(sm, lambda: sm.current_state_names()[-1] in ("StDone", "StFailed"), max_sim_s)
    return sm, posted


def leaf(sm: SmaccStateMachineBase) -> str:
    return sm.current_state_names()[-1]


# ------------------------------------------------------------------ named waypoints
def test_navigate_named_waypoint_goes_there_and_posts_its_waypoint_events(
    world: Callable[..., MoreNav2],
) -> None:
    nav2 = world()
    sm, posted = run(nav2, machine(CbNavigateNamedWaypoint, "c"))
    assert leaf(sm) == "StDone"
    assert nav2.navigation_goals(sm) == [pytest.approx((2.0, 1.5, 0.0))]
    waypoint_events = [e for e in posted.events if isinstance(e, (EvWaypoint, EvWaypointFinal))]
    assert [type(e) for e in waypoint_events] == [
        waypoint_event(2)[ClNav2Z, OrNav],
        EvWaypointFinal[ClNav2Z, OrNav],
    ]
    assert (waypoint_events[0].waypoint_index, waypoint_events[0].name) == (2, "c")
    assert sm.requires_component(CpWaypointNavigator).current_index == 3


def test_navigate_named_waypoint_fails_naming_an_unknown_name_and_sends_nothing(
    world: Callable[..., MoreNav2],
) -> None:
    nav2 = world()
    sm, _ = run(nav2, machine(CbNavigateNamedWaypoint, "dock"))
    assert leaf(sm) == "StFailed"
    assert sm.transition_log[-1].event.reason == (
        "CbNavigateNamedWaypoint: waypoint_name 'dock' is not a waypoint of CpWaypointNavigator "
        "(named: a, b, c)"
    )
    assert nav2.navigation_goals(sm) == []


def test_waypoint_behaviors_refuse_empty_names_when_built() -> None:
    with pytest.raises(ValueError, match="CbNavigateNamedWaypoint: waypoint_name is empty"):
        CbNavigateNamedWaypoint("")
    with pytest.raises(
        TypeError, match="CbNavigateNextWaypointUntilReached: goal_waypoint_name must be a str"
    ):
        CbNavigateNextWaypointUntilReached(3)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="CbSeekWaypoint: give exactly one of waypoint_name and count"):
        CbSeekWaypoint("a", count=1)
    with pytest.raises(ValueError, match="CbSeekWaypoint: count must be an int >= 0, got -1"):
        CbSeekWaypoint(count=-1)


SmUntil = chain("SmUntil", [], last_target="StUntil")
add_until_reached(SmUntil, "StUntil", "b")


def test_until_reached_loops_leg_by_leg_and_leaves_on_the_goal_waypoint(
    world: Callable[..., MoreNav2],
) -> None:
    nav2 = world()
    sm, posted = run(nav2, SmUntil)
    assert leaf(sm) == "StDone"
    assert nav2.navigation_goals(sm) == [pytest.approx((1.0, 0.0, 0.0)), pytest.approx((2.0, 0.5, 1.0))]
    assert [r.key() for r in sm.transition_log] == [
        ("StUntil", "StUntil", "SUCCESS"),
        ("StUntil", "StDone", "SUCCESS"),
    ]
    reached = posted.of(EvGoalWaypointReached)
    assert [(e.waypoint_index, e.name) for e in reached] == [(1, "b")]
    # The goal leg's own EvCbSuccess came after EvGoalWaypointReached, and did not re-enter StUntil.
    assert isinstance(sm.transition_log[-1].event, EvGoalWaypointReached)


SmBehind = chain("SmBehind", [(CbSeekWaypoint, ("c",), {}), (CbNavigateNextWaypointUntilReached, ("a",), {})])


def test_until_reached_fails_when_the_goal_is_behind_the_cursor(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, SmBehind)
    assert leaf(sm) == "StFailed"
    assert sm.transition_log[-1].event.reason == (
        "CbNavigateNextWaypointUntilReached: goal_waypoint_name 'a' is waypoint 0, behind the cursor "
        "(at waypoint 2)"
    )
    assert nav2.navigation_goals(sm) == []


def test_seek_waypoint_moves_the_cursor_without_navigating(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, machine(CbSeekWaypoint, "c"))
    assert leaf(sm) == "StDone" and sm.transition_log[-1].event.index == 2
    assert nav2.navigation_goals(sm) == []
    sm, _ = run(nav2, machine(CbSeekWaypoint, count=1))
    assert sm.transition_log[-1].event.index == 1
    sm, _ = run(nav2, machine(CbSeekWaypoint, "z"))
    assert leaf(sm) == "StFailed"
    assert "CbSeekWaypoint: waypoint_name 'z' is not a waypoint" in sm.transition_log[-1].event.reason


def test_find_searches_forward_from_the_cursor_then_backwards_as_smacc2() -> None:
    navigator = CpWaypointNavigator()
    navigator.waypoints = [Waypoint(float(i), 0.0, 0.0, name) for i, name in enumerate("xyxz")]
    assert navigator.find("x") == 0
    navigator.current_index = 1
    assert navigator.find("x") == 2  # the one ahead wins over the one behind
    navigator.current_index = 3
    assert navigator.find("y") == 1 and navigator.find("x") == 2  # nearest behind
    assert navigator.find("w") is None
    with pytest.raises(ValueError, match=r"no waypoint named 'w' \(named: x, y, x, z\)"):
        navigator.seek_name("w")


# ------------------------------------------------------------------ waypoint event dispatcher
class _RecordingClient:
    def __init__(self) -> None:
        self.posted: list[SmaccEvent] = []

    def own_event(self, template: type[SmaccEvent]) -> type[SmaccEvent]:
        return template[ClNav2Z, OrNav]

    def post_event(self, event: SmaccEvent) -> None:
        self.posted.append(event)


def test_dispatcher_posts_per_index_events_and_final_but_none_past_44() -> None:
    client = _RecordingClient()
    dispatcher = WaypointEventDispatcher(client)  # type: ignore[arg-type]
    dispatcher.post_waypoint_event(3, Waypoint(0.0, 0.0, 0.0, "d"), is_last=False)
    dispatcher.post_waypoint_event(45, Waypoint(0.0, 0.0), is_last=False)
    dispatcher.post_waypoint_event(46, Waypoint(0.0, 0.0), is_last=True)
    assert [type(e) for e in client.posted] == [
        waypoint_event(3)[ClNav2Z, OrNav],
        EvWaypointFinal[ClNav2Z, OrNav],
    ]
    assert (client.posted[0].waypoint_index, client.posted[0].name) == (3, "d")
    assert client.posted[1].waypoint_index == 46


# ------------------------------------------------------------------ CbRetry
def test_retry_runs_fresh_attempts_until_one_succeeds(world: Callable[..., MoreNav2]) -> None:
    nav2 = world(navigate=("aborted", "aborted", "succeeded"))
    sm, _ = run(nav2, machine(CbRetry, CbNavigateNextWaypoint, retries=3, retry_delay_s=2.0))
    assert leaf(sm) == "StDone"
    event = sm.transition_log[-1].event
    assert (event.attempts, event.behavior) == (3, "CbNavigateNextWaypoint")
    goals = sm.requires_client(ClNav2Z).action_log().goals
    assert len(goals) == 3
    stamps = [g.pose.header.stamp.sec + g.pose.header.stamp.nanosec * 1e-9 for g in goals]
    assert all(later - earlier >= 2.0 for earlier, later in itertools.pairwise(stamps))  # the retry delay


def test_retry_fails_after_the_last_attempt_with_its_reason(world: Callable[..., MoreNav2]) -> None:
    nav2 = world(navigate=("aborted", "aborted", "succeeded"))
    sm, _ = run(nav2, machine(CbRetry, CbNavigateNextWaypoint, retries=1))
    assert leaf(sm) == "StFailed"
    event = sm.transition_log[-1].event
    assert event.attempts == 2
    assert event.reason == "aborted (error_code 204: Goal outside map)"
    assert len(sm.requires_client(ClNav2Z).action_log().goals) == 2


def test_retry_passes_the_attempts_other_events_to_the_machine(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, posted = run(nav2, machine(CbRetry, CbNavigateNextWaypointUntilReached, "a"))
    assert leaf(sm) == "StDone"
    reached = posted.of(EvGoalWaypointReached)
    assert [type(e) for e in reached] == [EvGoalWaypointReached[CbNavigateNextWaypointUntilReached, OrNav]]
    # The attempt's own EvCbSuccess stayed inside CbRetry, which posted its own.
    assert not posted.of(EvCbSuccess[CbNavigateNextWaypointUntilReached, OrNav])
    assert isinstance(sm.transition_log[-1].event, EvCbSuccess[CbRetry, OrNav])


def test_retry_exits_the_running_attempt_when_its_state_exits(world: Callable[..., MoreNav2]) -> None:
    nav2 = world(navigate=("hold",))
    sm = nav2.start(machine(CbRetry, CbNavigateNextWaypoint))
    nav2.clock.t += 1.0
    sm.update()
    retry = next(b for state in sm.active_states() for _, b in state.behaviors if isinstance(b, CbRetry))
    attempt = retry.current
    assert isinstance(attempt, CbNavigateNextWaypoint) and attempt.ticket is not None
    sm.stop()
    assert attempt.ticket.abandoned and attempt.ticket.cancel_requested
    assert retry.current is None


def test_retry_checks_its_arguments_and_the_behaviors_when_built() -> None:
    with pytest.raises(TypeError, match="CbRetry: behavior_type must be a client behavior class, got 3"):
        CbRetry(3)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="CbRetry: retries must be an int >= 0, got -1"):
        CbRetry(CbNavigateNextWaypoint, retries=-1)
    with pytest.raises(ValueError, match="CbRetry: retry_delay_s must be a finite number of seconds >= 0"):
        CbRetry(CbNavigateNextWaypoint, retry_delay_s=math.nan)
    with pytest.raises(ValueError, match="CbNavigateForward: need a non-zero distance"):
        CbRetry(CbNavigateForward, 0.0)


# ------------------------------------------------------------------ CbRotateLookAt
def test_rotate_look_at_spins_to_face_the_point(world: Callable[..., MoreNav2]) -> None:
    nav2 = world(start_pose=(-2.0, -0.5, 0.5))
    sm, _ = run(nav2, machine(CbRotateLookAt, -2.0, 1.5))
    assert leaf(sm) == "StDone"
    spins = sm.requires_client(ClNav2Z).action_log(SPIN).goals
    assert [g.target_yaw for g in spins] == [pytest.approx(math.pi / 2 - 0.5)]


def test_rotate_look_at_fails_when_standing_on_the_point(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, machine(CbRotateLookAt, -2.0, -0.5))
    assert leaf(sm) == "StFailed"
    assert "CbRotateLookAt: the robot at (-2.000, -0.500) is within 0.01 m of the point" in (
        sm.transition_log[-1].event.reason
    )
    with pytest.raises(ValueError, match="CbRotateLookAt: y must be a finite number, got nan"):
        CbRotateLookAt(0.0, math.nan)


# ------------------------------------------------------------------ CbWaitTransform
def test_wait_transform_succeeds_once_the_transform_appears(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    nav2.frames[("map", "laser")] = (Transform.from_xy_yaw(1.0, 2.0, 0.3), 3.0)
    sm, _ = run(nav2, machine(CbWaitTransform, "map", "laser", timeout_s=10.0))
    assert leaf(sm) == "StDone"
    record = sm.transition_log[-1]
    assert record.stamp_s >= 3.0
    assert (record.event.transform.x, record.event.transform.y) == (1.0, 2.0)


def test_wait_transform_fails_after_its_timeout_naming_the_frames(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, machine(CbWaitTransform, "map", "laser", timeout_s=4.0))
    assert leaf(sm) == "StFailed"
    record = sm.transition_log[-1]
    assert record.stamp_s >= 4.0
    assert record.event.reason.startswith("CbWaitTransform: no transform map <- laser within 4.0 s: ")
    assert "does not exist" in record.event.reason
    with pytest.raises(ValueError, match="CbWaitTransform: reference_frame must name a frame, got ''"):
        CbWaitTransform("map", "")
    with pytest.raises(ValueError, match="CbWaitTransform: timeout_s must be > 0 s and finite, got 0"):
        CbWaitTransform("map", "odom", timeout_s=0)


# ------------------------------------------------------------------ SLAM pause / resume
def test_pause_then_resume_slam(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, machine(CbPauseSlam))
    assert leaf(sm) == "StDone" and nav2.slam_paused
    assert sm.requires_component(CpSlamToolbox).state is SlamToolboxState.PAUSED
    assert sm.transition_log[-1].event.state is SlamToolboxState.PAUSED
    sm, _ = run(nav2, machine(CbResumeSlam))
    assert leaf(sm) == "StDone" and not nav2.slam_paused


def test_pause_slam_fails_when_the_node_refuses_and_keeps_the_state(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    nav2.slam_refuses = True
    sm, _ = run(nav2, machine(CbPauseSlam))
    assert leaf(sm) == "StFailed"
    assert sm.transition_log[-1].event.reason == (
        "CbPauseSlam: '/slam/pause_new_measurements' refused to switch to paused: not now"
    )
    assert sm.requires_component(CpSlamToolbox).state is SlamToolboxState.RESUMED


def test_pause_slam_fails_after_the_timeout_without_a_server(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    nav2.slam_up = False
    sm, _ = run(nav2, machine(CbPauseSlam))
    assert leaf(sm) == "StFailed"
    assert sm.transition_log[-1].stamp_s >= 5.0
    assert sm.transition_log[-1].event.reason == (
        "CbPauseSlam: service '/slam/pause_new_measurements' not available within 5 s"
    )


# ------------------------------------------------------------------ CpCostmapSwitch
def _switch(nav2: MoreNav2) -> tuple[SmaccStateMachineBase, CpCostmapSwitch]:
    sm = nav2.start(machine(CbSeekWaypoint, count=0))
    return sm, sm.requires_component(CpCostmapSwitch)


def test_costmap_switch_sets_the_layers_enabled_parameter(world: Callable[..., MoreNav2]) -> None:
    nav2 = world()
    sm, switch = _switch(nav2)
    answers: list[tuple[bool, str]] = []
    switch.disable(StandardLayers.GLOBAL_OBSTACLES_LAYER, lambda ok, why: answers.append((ok, why)))
    switch.disable("local_costmap/inflation_layer", lambda ok, why: answers.append((ok, why)))
    assert nav2.drive(sm, lambda: len(answers) == 2, 5.0)
    assert answers == [(True, ""), (True, "")]
    assert nav2.costmap_params["/global_costmap/global_costmap"]["obstacle_layer.enabled"] is False
    assert nav2.costmap_params["/local_costmap/local_costmap"]["inflation_layer.enabled"] is False
    assert nav2.costmap_params["/local_costmap/local_costmap"]["obstacle_layer.enabled"] is True
    switch.enable(StandardLayers.GLOBAL_OBSTACLES_LAYER, lambda ok, why: answers.append((ok, why)))
    assert nav2.drive(sm, lambda: len(answers) == 3, 5.0)
    assert nav2.costmap_params["/global_costmap/global_costmap"]["obstacle_layer.enabled"] is True
    assert switch.enabled == {"global_costmap/obstacle_layer": True, "local_costmap/inflation_layer": False}


def test_costmap_switch_reports_a_refused_parameter_and_rejects_unknown_layers(
    world: Callable[..., MoreNav2],
) -> None:
    nav2 = world()
    sm, switch = _switch(nav2)
    assert switch.register_layer("/global_costmap/voxel_layer/") == "global_costmap/voxel_layer"
    assert switch.exists("global_costmap/voxel_layer") and not switch.exists("global_costmap/keepout")
    answers: list[tuple[bool, str]] = []
    switch.disable("global_costmap/voxel_layer", lambda ok, why: answers.append((ok, why)))
    assert nav2.drive(sm, lambda: bool(answers), 5.0)
    assert answers == [
        (
            False,
            "CpCostmapSwitch: /global_costmap/global_costmap refused voxel_layer.enabled=False: "
            "Parameter voxel_layer.enabled is not declared",
        )
    ]
    assert "global_costmap/voxel_layer" not in switch.enabled
    with pytest.raises(ValueError, match=r"layer 'global_costmap/keepout' is not registered; registered: \["):
        switch.enable("global_costmap/keepout")
    with pytest.raises(ValueError, match=r"layer must be '<costmap>/<layer>'.*got 'obstacle_layer'"):
        switch.register_layer("obstacle_layer")


# ------------------------------------------------------------------ CpWaypointsVisualizer
def test_visualizer_publishes_spheres_and_labels_and_colors_reached_ones(
    world: Callable[..., MoreNav2],
) -> None:
    nav2 = world()
    sm = nav2.start(machine(CbSeekWaypoint, count=0))
    visualizer = sm.requires_component(CpWaypointsVisualizer)
    publisher = visualizer._pub
    assert isinstance(publisher, RecordingPublisher)
    sm.update()  # the first poll publishes
    first = publisher.messages[0].markers
    assert [(m.ns, m.id) for m in first] == [
        (ns, i) for i in range(3) for ns in ("waypoints", "waypoints_labels")
    ]
    assert [m.text for m in first if m.ns == "waypoints_labels"] == ["a", "b", "c"]
    assert all(m.color == PENDING for m in first) and all(m.header.frame_id == "map" for m in first)
    assert (first[1].pose.position.x, first[1].pose.position.z) == (1.0, 0.3)
    navigator = sm.requires_component(CpWaypointNavigator)
    navigator.on_reached(0)  # as CbNavigateNextWaypoint does when Nav2 reports success
    nav2.clock.t += 1.0
    sm.update()
    last = publisher.messages[-1].markers
    assert [m.color == REACHED for m in last] == [True, True, False, False, False, False]
    count = len(publisher.messages)
    nav2.clock.t += 1.0
    sm.update()
    assert len(publisher.messages) == count  # nothing changed, nothing published
