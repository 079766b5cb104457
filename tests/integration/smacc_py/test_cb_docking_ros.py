"""CbDockRobot and CbUndockRobot on the smacc_py runtime, through ClNav2Z over DDS, against the real
docking_server and the fake docking robot (tests/helpers/docking_stack.py)."""

from __future__ import annotations

from typing import Any

import pytest

pytest.importorskip("smacc2_msgs.msg", reason="smacc2_msgs is not built (run the interface build)")
pytest.importorskip("nav2_msgs.action", reason="nav2_msgs is not built (run the interface build)")

from rclpy.parameter import Parameter

from navsuite_testing.ros import wait_until
from smacc_py.clients.cl_nav2z import CbDockRobot, CbUndockRobot, ClNav2Z
from smacc_py.core import (
    ABORT,
    SUCCESS,
    EvCbFailure,
    EvCbSuccess,
    Orthogonal,
    SmaccState,
    SmaccStateMachineBase,
    Transition,
)
from smacc_py.ros.runtime import SmaccRuntime
from tests.helpers.docking_stack import OVERRIDES, Docking

pytestmark = pytest.mark.ros


class OrDocking(Orthogonal):
    def on_initialize(self) -> None:
        self.create_client(ClNav2Z)


class SmDocking(SmaccStateMachineBase):
    """Dock at home_dock, then undock; any failure leads to StFailed."""

    initial_state = "StDock"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrDocking)


class StDock(SmaccState, parent=SmDocking):
    reactions = [Transition(EvCbSuccess[CbDockRobot, OrDocking], "StUndock", SUCCESS),
                 Transition(EvCbFailure[CbDockRobot, OrDocking], "StFailed", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrDocking, CbDockRobot, "home_dock", navigate_to_staging_pose=False)


class StUndock(SmaccState, parent=SmDocking):
    reactions = [Transition(EvCbSuccess[CbUndockRobot, OrDocking], "StDone", SUCCESS),
                 Transition(EvCbFailure[CbUndockRobot, OrDocking], "StFailed", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrDocking, CbUndockRobot)


type("StDone", (SmaccState,), {}, parent=SmDocking)
type("StFailed", (SmaccState,), {}, parent=SmDocking)


class SmDockingUnknown(SmaccStateMachineBase):
    initial_state = "StDockGarage"

    def on_initialize(self) -> None:
        self.create_orthogonal(OrDocking)


class StDockGarage(SmaccState, parent=SmDockingUnknown):
    reactions = [Transition(EvCbSuccess[CbDockRobot, OrDocking], "StDone", SUCCESS),
                 Transition(EvCbFailure[CbDockRobot, OrDocking], "StFailed", ABORT)]

    @classmethod
    def static_configure(cls) -> None:
        cls.configure_orthogonal(OrDocking, CbDockRobot, "garage", navigate_to_staging_pose=False)


type("StDone", (SmaccState,), {}, parent=SmDockingUnknown)
type("StFailed", (SmaccState,), {}, parent=SmDockingUnknown)


def _run(context: Any, sm_type: type[SmaccStateMachineBase]) -> tuple[Docking, SmaccRuntime]:
    stack = Docking(context, OVERRIDES)
    sim_time = [Parameter("use_sim_time", value=True)]
    runtime = SmaccRuntime(sm_type, context=context, parameter_overrides=sim_time)
    runtime.spin_in_background()
    runtime.start()
    return stack, runtime


def _leaf(runtime: SmaccRuntime) -> str:
    names = runtime.sm.current_state_names()
    return names[-1] if names else ""


def test_the_machine_docks_and_undocks(ros_context: Any) -> None:
    stack, runtime = _run(ros_context, SmDocking)
    try:
        wait_until(lambda: _leaf(runtime) in ("StDone", "StFailed"), 90.0, "the machine to finish")
        log = list(runtime.sm.transition_log)
        expected = [("StDock", "StUndock", "SUCCESS"), ("StUndock", "StDone", "SUCCESS")]
        assert [r.key() for r in log] == expected
        docked: Any = log[0].event
        assert (docked.error_code, docked.result.success, docked.result.num_retries) == (0, True, 0)
        assert stack.robot.distance_to_dock() > 0.6  # undocked back to the staging pose
    finally:
        runtime.shutdown()
        stack.harness.close()


def test_an_unknown_dock_posts_ev_cb_failure_with_dock_not_in_db(ros_context: Any) -> None:
    stack, runtime = _run(ros_context, SmDockingUnknown)
    try:
        wait_until(lambda: _leaf(runtime) in ("StDone", "StFailed"), 60.0, "the machine to finish")
        failure: Any = runtime.sm.transition_log[-1].event
        assert _leaf(runtime) == "StFailed"
        assert (failure.error_code, failure.result.success) == (901, False)
        assert "dock 'garage' is not in the dock database" in failure.error_msg
    finally:
        runtime.shutdown()
        stack.harness.close()
