"""sm_dance_bot's definition: it compiles and validates, and smacc-graph's Mermaid export draws it."""

from __future__ import annotations

import re

from smacc_py.core import to_mermaid
from smacc_py.core.model import compile_model
from smacc_py.ros.loader import load_state_machine
from smacc_py.state_machines.sm_dance_bot import (
    LOOPING_SUPERSTATES,
    MsDanceBotRecoveryMode,
    MsDanceBotRunMode,
    SmDanceBot,
    StFinalState,
)

SUPERSTATES = {"MsDanceBotRunMode", "SsRadialPattern1", "SsRadialPattern2", "SsRadialPattern3", "SsFPattern1",
               "SsSPattern1"}


def test_smacc_run_and_smacc_graph_find_the_machine_by_its_package_name() -> None:
    assert load_state_machine("sm_dance_bot") is SmDanceBot


def test_the_machine_compiles_with_every_declared_state_reachable() -> None:
    model = compile_model(SmDanceBot)
    names = {cls.__name__ for cls in model.chains}
    assert {"StAcquireSensors", "StEventCountDown", "StNavigateToWaypointsX", "StNavigateToWaypoint1",
            "MsDanceBotRecoveryMode", "StFinalState"} <= names
    assert {f"StRotateDegrees{i}" for i in range(1, 7)} <= names
    straight = {f"StNavigateReverse{i}" for i in range(1, 5)} | {"StNavigateForward1", "StNavigateForward2"}
    assert straight <= names
    assert {cls.__name__ for cls in model.superstates} == SUPERSTATES
    assert model.initial is MsDanceBotRunMode


def test_the_superstates_loop_and_the_recovery_mode_returns_through_deep_history() -> None:
    model = compile_model(SmDanceBot)
    assert [ss.total_iterations for ss in LOOPING_SUPERSTATES] == [2, 4, 2, 2, 2]
    recovery = [t for t in MsDanceBotRecoveryMode.reactions if t.is_history]
    assert recovery and all(t.target_name() == "History(MsDanceBotRunMode)" for t in recovery)
    assert StFinalState in model.chains


def test_the_mermaid_export_draws_every_state_and_superstate() -> None:
    text = to_mermaid(SmDanceBot)
    model = compile_model(SmDanceBot)
    drawn_states = set(re.findall(r"^\s*state (\w+)", text, flags=re.MULTILINE))
    assert {cls.__name__ for cls in model.chains} <= drawn_states
    superstate_boxes = set(re.findall(r"^\s*state (\w+) \{", text, flags=re.MULTILINE))
    assert superstate_boxes == SUPERSTATES
    for ss in ("SsRadialPattern1", "SsSPattern1", "SsFPattern1"):
        assert re.search(rf"{ss} --> \w+ : EvLoopEnd\[\w+\] / ENDLOOP", text), ss
    assert "MsDanceBotRecoveryMode --> MsDanceBotRunMode" in text and "(H*)" in text
