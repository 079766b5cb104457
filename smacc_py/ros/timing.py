"""Waiting on the machine clock from an async behavior's thread, so loops follow sim time.

``sleep_on_machine_clock`` returns when the machine clock (the node clock, /clock under
``use_sim_time``) has advanced by ``seconds``, or at once when the behavior's state exits. It polls the
clock every few wall milliseconds, which costs nothing and works whatever the simulation's speed.
It is for user code in async behaviors only: how late such a thread wakes depends on the machine's
load, so the shipped behaviors run their loops on the executor (ISmaccUpdatable, node-clock timers).
"""

from __future__ import annotations

from smacc_py.core import SmaccAsyncClientBehavior

POLL_WALL_S = 0.005


def sleep_on_machine_clock(behavior: SmaccAsyncClientBehavior, seconds: float) -> bool:
    """Sleep ``seconds`` of machine time; returns False when shutdown was requested meanwhile."""
    sm = behavior.get_state_machine()
    until = sm.now() + seconds
    while sm.now() < until:
        if behavior.wait_for_shutdown(POLL_WALL_S):
            return False
    return not behavior.is_shutdown_requested()
