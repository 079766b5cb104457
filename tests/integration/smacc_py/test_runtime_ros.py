"""SmaccRuntime's executor thread survives a callback that raises (rclpy's spin() would end there)."""

from __future__ import annotations

import logging

import pytest

from navsuite_testing.ros import wait_until
from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1

pytestmark = pytest.mark.ros


def test_a_callback_that_raises_is_logged_and_the_mission_still_ends(stack, caplog) -> None:  # type: ignore[no-untyped-def]
    """Without the guard the executor thread ends at the exception: /clock stops reaching the
    machine, whose timeouts then never fire, and the mission hangs in its current state."""
    _fake, runtime = stack(SmNav2Test1)
    calls: list[int] = []

    def explode() -> None:
        calls.append(1)
        if len(calls) == 1:
            raise RuntimeError("a broken callback")

    timer = runtime.node.create_timer(0.05, explode)
    with caplog.at_level(logging.ERROR, logger="smacc_py"):
        wait_until(lambda: runtime.sm.current_state_names() == ["StFinalState"], 60.0, "the mission to end")
    runtime.node.destroy_timer(timer)
    assert len(calls) > 1, "the executor stopped calling back after the exception"
    assert any("a callback raised" in r.getMessage() and r.exc_info for r in caplog.records), caplog.text
