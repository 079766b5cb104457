"""A BT leaf's ``server_timeout`` counts sim time, but not the sim time a lockstep simulator may still
run on (up to its lead) while it waits for the answer.

Nav2 Jazzy's file sets default_server_timeout 20 ms; the simulator's lead is 50 ms. Before this rule
a goal sent to controller_server failed "timed out after 20 ms waiting for action server 'follow_path'
to acknowledge the goal request" whenever the answer took more than 20 ms of that lead.
"""

from __future__ import annotations

from typing import Any

import pytest

from nav_stack.ros.bt_nodes import context as context_module
from nav_stack.ros.bt_nodes.context import BtRosContext
from ros_tools.runtime.lockstep import REQUEST_HOLD


class _Clocks:
    """Hand-driven clocks (s): ``sim`` is the node's, ``wall`` the steady one."""

    def __init__(self) -> None:
        self.sim = 10.0
        self.wall = 100.0


class _Future:
    def done(self) -> bool:
        return False

    def add_done_callback(self, callback: Any) -> None:
        pass


def _context(clocks: _Clocks) -> BtRosContext:
    return BtRosContext(node=None, wall_clock=lambda: clocks.wall, clock=lambda: clocks.sim)  # type: ignore[arg-type]


def test_outside_lockstep_the_wait_is_the_node_clocks_as_in_nav2() -> None:
    clocks = _Clocks()
    ctx = _context(clocks)
    request = ctx.start_timed(_Future())  # no participant in this process: nothing holds
    assert request.held_until is None
    clocks.sim += 0.025
    assert ctx.waited_ms(request) == pytest.approx(25.0)


def test_sim_time_within_the_hold_does_not_count_and_counts_again_after_it(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(context_module, "hold_process", lambda *args, **kwargs: True)
    clocks = _Clocks()
    ctx = _context(clocks)
    request = ctx.start_timed(_Future())
    clocks.sim += 0.050  # the simulator ran on by its whole lead while the server was busy
    clocks.wall += 0.5
    assert ctx.waited_ms(request) == 0.0
    clocks.wall += REQUEST_HOLD  # a server that never answers: the hold ends, sim time counts
    clocks.sim += 0.010
    assert ctx.waited_ms(request) == pytest.approx(10.0)
    clocks.sim += 0.015
    assert ctx.waited_ms(request) == pytest.approx(25.0)
