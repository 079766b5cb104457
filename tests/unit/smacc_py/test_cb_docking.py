"""CbDockRobot and CbUndockRobot through ClNav2Z on a scripted docking server (smacc_docking_fakes):
the goals they send, EvCbSuccess / EvCbFailure with the server's error code, cancel on state exit."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from nav2_msgs.action import DockRobot, UndockRobot

from smacc_py.clients.cl_nav2z import CbDockRobot, CbUndockRobot, ClNav2Z
from smacc_py.clients.cl_nav2z.cb_docking import DOCK_ROBOT, UNDOCK_ROBOT
from smacc_py.core import EvActionAborted, EvCbFailure, EvCbSuccess, SmaccStateMachineBase
from tests.helpers.smacc_docking_fakes import DockingNav2, PostedEvents
from tests.helpers.smacc_nav2z_more_fakes import OrNav, chain


@pytest.fixture
def world() -> Iterator[Callable[..., DockingNav2]]:
    made: list[DockingNav2] = []

    def make(**docking: Any) -> DockingNav2:
        made.append(DockingNav2(docking))
        return made[-1]

    yield make
    for each in made:
        each.close()


def leaf(sm: SmaccStateMachineBase) -> str:
    return sm.current_state_names()[-1]


def run(nav2: DockingNav2, sm_type: type[SmaccStateMachineBase]
        ) -> tuple[SmaccStateMachineBase, PostedEvents]:
    posted = PostedEvents()
    sm = nav2.start(sm_type)
    sm.add_observer(posted)
    assert nav2.drive(sm, lambda: leaf(sm) in ("StDone", "StFailed"), 60.0)
    return sm, posted


def goals(sm: SmaccStateMachineBase, key: str) -> list[Any]:
    return sm.requires_client(ClNav2Z).action_log(key).goals  # type: ignore[attr-defined]


def test_dock_then_undock_succeed_and_send_the_goals(world: Callable[..., DockingNav2]) -> None:
    nav2 = world()
    sm, posted = run(nav2, chain("SmDockUndock", [
        (CbDockRobot, ("home_dock",), {"navigate_to_staging_pose": False}),
        (CbUndockRobot, (), {"max_undocking_time": 20.0})]))
    assert leaf(sm) == "StDone"
    [dock] = goals(sm, DOCK_ROBOT)
    assert (dock.use_dock_id, dock.dock_id, dock.navigate_to_staging_pose) == (True, "home_dock", False)
    assert dock.max_staging_time == pytest.approx(1000.0)
    [undock] = goals(sm, UNDOCK_ROBOT)
    assert (undock.dock_type, undock.max_undocking_time) == ("", pytest.approx(20.0))
    successes = posted.of(EvCbSuccess)
    expected = [EvCbSuccess[CbDockRobot, OrNav], EvCbSuccess[CbUndockRobot, OrNav]]
    assert [type(e) for e in successes] == expected
    assert isinstance(successes[0].result, DockRobot.Result) and successes[0].result.success
    assert successes[0].error_code == 0


def test_a_dock_by_pose_sends_the_pose_and_type(world: Callable[..., DockingNav2]) -> None:
    nav2 = world()
    sm, _ = run(nav2, chain("SmDockPose", [
        (CbDockRobot, (), {"dock_pose": (1.0, 2.0, math.pi / 2), "dock_type": "simple_charging_dock"})]))
    [dock] = goals(sm, DOCK_ROBOT)
    assert (dock.use_dock_id, dock.dock_type) == (False, "simple_charging_dock")
    assert dock.dock_pose.header.frame_id == "map"
    assert (dock.dock_pose.pose.position.x, dock.dock_pose.pose.position.y) == (1.0, 2.0)
    assert dock.dock_pose.pose.orientation.z == pytest.approx(math.sin(math.pi / 4))


@pytest.mark.parametrize(("code", "name"), [(901, "DOCK_NOT_IN_DB"), (904, "FAILED_TO_DETECT_DOCK"),
                                            (906, "FAILED_TO_CHARGE")])
def test_a_failed_docking_posts_ev_cb_failure_with_the_servers_code(world: Callable[..., DockingNav2],
                                                                    code: int, name: str) -> None:
    assert getattr(DockRobot.Result, name) == code
    nav2 = world(dock_robot=[("aborted", code, f"{name.lower()} happened", 2)])
    sm, posted = run(nav2, chain("SmDockFails", [(CbDockRobot, ("home_dock",), {})]))
    assert leaf(sm) == "StFailed"
    failures = posted.of(EvCbFailure)
    assert [type(e) for e in failures] == [EvCbFailure[CbDockRobot, OrNav]]
    failure = failures[0]
    assert (failure.error_code, failure.error_msg) == (code, f"{name.lower()} happened")
    assert (failure.result.success, failure.result.num_retries) == (False, 2)
    assert posted.of(EvActionAborted)[0].action == DOCK_ROBOT  # ClNav2Z's own event names the action


def test_a_failed_undocking_posts_ev_cb_failure(world: Callable[..., DockingNav2]) -> None:
    nav2 = world(undock_robot=[("aborted", UndockRobot.Result.DOCK_NOT_VALID, "no dock information", 0)])
    sm, posted = run(nav2, chain("SmUndockFails", [(CbUndockRobot, ("simple_charging_dock",), {})]))
    assert leaf(sm) == "StFailed"
    [failure] = posted.of(EvCbFailure)
    assert (type(failure), failure.error_code) == (EvCbFailure[CbUndockRobot, OrNav], 902)
    assert goals(sm, UNDOCK_ROBOT)[0].dock_type == "simple_charging_dock"


def test_the_behaviors_refuse_bad_arguments_when_built() -> None:
    with pytest.raises(ValueError, match="CbDockRobot: give exactly one of dock_id and dock_pose"):
        CbDockRobot()
    with pytest.raises(ValueError, match="CbDockRobot: give exactly one of dock_id and dock_pose"):
        CbDockRobot("home_dock", dock_pose=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="dock_pose must be 3 finite numbers"):
        CbDockRobot(dock_pose=(0.0, math.nan, 0.0))
    with pytest.raises(ValueError, match="max_staging_time must be > 0"):
        CbDockRobot("home_dock", max_staging_time=0.0)
    with pytest.raises(TypeError, match="CbUndockRobot: dock_type must be a str"):
        CbUndockRobot(3)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="max_undocking_time must be > 0"):
        CbUndockRobot(max_undocking_time=-1.0)
