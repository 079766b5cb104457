"""cl_nav2z pieces on the scripted clients of smacc_fake_nav: CbWaitPose, CbStopNavigation (the shipped
behaviors) and the planner presets against nav_stack's configuration."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from nav2_msgs.action import Spin

from smacc_py.clients.cl_nav2z import (
    CbNavigateGlobalPosition,
    CbStopNavigation,
    CbWaitPose,
    ClNav2Z,
    CpGoalCheckerSwitcher,
    CpPlannerSwitcher,
    CpPose,
)
from smacc_py.clients.cl_nav2z.cp_switchers import PRESETS, SMACC2_ONLY_PRESETS
from smacc_py.clients.cl_ros2_timer import CbTimerCountdownOnce, ClRos2Timer
from smacc_py.core import (
    ABORT,
    CANCEL,
    SUCCESS,
    EvActionCancelled,
    EvActionResult,
    EvActionSucceeded,
    EvCbFailure,
    EvCbSuccess,
    EvTimer,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1, SmNav2Test1Params
from tests.helpers.smacc_fake_nav import Nav2Script, RecordingPublisher, ScriptedNav2
from tests.helpers.smacc_stand_ins import ScriptedClNav2Z

WAIT_POSE_TIMEOUT_S = 5.0
NAV2_PARAMS = Path(__file__).resolve().parents[3] / "config" / "nav2_params.yaml"


class OrNav(Orthogonal):
    def on_initialize(self) -> None:
        client = self.create_client(ClNav2Z)
        client.create_component(CpPose, "base_link", "map")


class OrTime(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClRos2Timer)


class _Sm(SmaccStateMachineBase):
    def on_initialize(self) -> None:
        self.create_orthogonal(OrNav)
        self.create_orthogonal(OrTime)


# ------------------------------------------------------------------ CbWaitPose
class SmWaitPose(_Sm):
    initial_state = "StWaitPose"


class StWaitPose(SmaccState, parent=SmWaitPose):
    reactions = [
        Transition(EvCbSuccess[CbWaitPose, OrNav], "StPoseKnown", SUCCESS),
        Transition(EvCbFailure[CbWaitPose, OrNav], "StNoPose", ABORT),
    ]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbWaitPose, timeout_s=WAIT_POSE_TIMEOUT_S)


class StPoseKnown(SmaccState, parent=SmWaitPose):
    pass


class StNoPose(SmaccState, parent=SmWaitPose):
    pass


# ------------------------------------------------------------------ CbStopNavigation
# The goal belongs to the superstate, so it is still owned (not abandoned by a state exit) when
# CbStopNavigation runs in an inner state: its cancellation can only come from CbStopNavigation.
class SmStop(_Sm):
    initial_state = "SsNavigating"


class SsNavigating(SmaccState, parent=SmStop):
    inner_initial_state = "StiDriving"

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbNavigateGlobalPosition, 1.0, 0.0, 0.0)


class StiDriving(SmaccState, parent=SsNavigating):
    reactions = [Transition(EvTimer[CbTimerCountdownOnce, OrTime], "StiStopping", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrTime, CbTimerCountdownOnce, 2.0)


class StiStopping(SmaccState, parent=SsNavigating):
    reactions = [Transition(EvCbSuccess[CbStopNavigation, OrNav], "StiStopped", SUCCESS)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrNav, CbStopNavigation)


class StiStopped(SmaccState, parent=SsNavigating):
    reactions = [Transition(EvActionCancelled[ClNav2Z, OrNav], "StGoalCancelled", CANCEL)]


class StGoalCancelled(SmaccState, parent=SmStop):
    pass


# ------------------------------------------------------------------ remapped action names
class OrRemapped(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClNav2Z, action_names={"spin": "my_spin"})


class SmRemapped(SmaccStateMachineBase):
    initial_state = "StIdle"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrRemapped)


class StIdle(SmaccState, parent=SmRemapped):
    reactions = [Transition(EvActionResult[ClNav2Z, OrRemapped], "StResult", SUCCESS)]


class StResult(SmaccState, parent=SmRemapped):
    reactions = [Transition(EvActionSucceeded[ClNav2Z, OrRemapped], "StSpun", SUCCESS)]


class StSpun(SmaccState, parent=SmRemapped):
    pass


@pytest.fixture
def world() -> Iterator[Callable[..., ScriptedNav2]]:
    made: list[ScriptedNav2] = []

    def make(**script: Any) -> ScriptedNav2:
        made.append(ScriptedNav2(Nav2Script(**script)))
        return made[-1]

    yield make
    for each in made:
        each.close()


def _leaf(sm: SmaccStateMachineBase) -> str:
    return sm.current_state_names()[-1]


def test_wait_pose_succeeds_with_the_pose_once_tf_has_it(world: Callable[..., ScriptedNav2]) -> None:
    nav2 = world()
    sm = nav2.start(SmWaitPose)
    assert nav2.drive(sm, lambda: _leaf(sm) != "StWaitPose")
    assert _leaf(sm) == "StPoseKnown"
    assert sm.transition_log[-1].event.pose == pytest.approx(nav2.script.start_pose)


def test_wait_pose_fails_after_its_timeout_saying_why(world: Callable[..., ScriptedNav2]) -> None:
    nav2 = world(tf_available=False)
    sm = nav2.start(SmWaitPose)
    assert nav2.drive(sm, lambda: _leaf(sm) != "StWaitPose")
    assert _leaf(sm) == "StNoPose"
    record = sm.transition_log[-1]
    assert record.stamp_s >= WAIT_POSE_TIMEOUT_S
    assert record.event.reason.startswith(f"no robot pose within {WAIT_POSE_TIMEOUT_S} s: ")
    assert "does not exist" in record.event.reason  # the TF error


def test_stop_navigation_cancels_the_running_goal_stops_the_robot_and_succeeds(
    world: Callable[..., ScriptedNav2],
) -> None:
    nav2 = world(navigate=("hold",))
    sm = nav2.start(SmStop)
    assert nav2.drive(sm, lambda: _leaf(sm) == "StGoalCancelled", max_sim_s=30.0)
    assert [r.key() for r in sm.transition_log] == [
        ("StiDriving", "StiStopping", "SUCCESS"),
        ("StiStopping", "StiStopped", "SUCCESS"),  # EvCbSuccess[CbStopNavigation, OrNav]
        ("StiStopped", "StGoalCancelled", "CANCEL"),  # the still-owned goal ended CANCELED
    ]
    assert len(nav2.navigation_goals(sm)) == 1
    last = nav2.base.twists[-1]
    assert (last.linear.x, last.angular.z) == (0.0, 0.0)


def test_planner_presets_name_only_plugins_nav_stack_declares() -> None:
    params = yaml.safe_load(NAV2_PARAMS.read_text())
    planners = params["planner_server"]["ros__parameters"]["planner_plugins"]
    controller_server = params["controller_server"]["ros__parameters"]
    controllers = controller_server["controller_plugins"]
    for name, (planner, controller) in PRESETS.items():
        assert (planner, controller) in [(p, c) for p in planners for c in controllers], name
    assert CpGoalCheckerSwitcher().default_goal_checker in controller_server["goal_checker_plugins"]
    for name, (planner, controller, _) in SMACC2_ONLY_PRESETS.items():  # refused for a reason
        assert planner not in planners or controller not in controllers, name


def test_set_preset_refuses_smacc2_only_presets_naming_the_plugin(world: Callable[..., ScriptedNav2]) -> None:
    sm = world().start(SmNav2Test1, config=SmNav2Test1Params())
    switcher = sm.requires_component(CpPlannerSwitcher)
    switcher.set_default_planners()
    sent = switcher._planner_pub
    assert isinstance(sent, RecordingPublisher)
    assert [m.data for m in sent.messages] == ["GridBased"]
    with pytest.raises(ValueError, match=r"preset 'backward' selects planner 'BackwardGlobalPlanner' and "
                                         r"controller 'BackwardLocalPlanner'.*use CbNavigateBackwards"):
        switcher.set_preset("backward")
    with pytest.raises(ValueError, match=r"unknown preset 'sideways'; known: \['default'\]"):
        switcher.set_preset("sideways")
    assert [m.data for m in sent.messages] == ["GridBased"]  # nothing published by the refusals
    assert (switcher.desired_planner, switcher.desired_controller) == PRESETS["default"]


def test_action_payloads_name_the_key_even_when_the_server_name_is_remapped(
    world: Callable[..., ScriptedNav2],
) -> None:
    nav2 = world()
    sm = nav2.start(SmRemapped)
    client = sm.requires_client(ClNav2Z)
    assert isinstance(client, ScriptedClNav2Z)
    client.send_goal("spin", Spin.Goal())
    assert nav2.drive(sm, lambda: _leaf(sm) == "StSpun", max_sim_s=5.0)
    assert client.action_log("spin").action_name == "my_spin"
    result, succeeded = (record.event for record in list(sm.transition_log)[-2:])
    assert type(result) is EvActionResult[ClNav2Z, OrRemapped]
    for event in (result, succeeded):
        assert (event.action, event.error_code, event.error_msg) == ("spin", 0, "")
