"""Waiting without blocking: coroutines (run by :func:`.coroutines.spawn`) that suspend on one-shot
timers and futures.

Why: no callback in the suite may block its executor (one thread runs every callback of a process).
A coroutine awaits these instead of sleeping: the executor serves everything else meanwhile, and
nothing runs for the coroutine until the timer fires or the future completes.

The clock decides what "seconds" means: the node's own clock by default (sim time under
``use_sim_time``, so a wait lasts the same sim time however fast the simulation runs) or a steady
clock for safety nets that must hold in wall time (a peer that never answers).
"""

from __future__ import annotations

from typing import Any

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.task import Future

from ros_tools.runtime.coroutines import until


def steady_clock() -> Clock:
    """A monotonic wall clock, for timeouts that are safety nets rather than behaviour."""
    return Clock(clock_type=ClockType.STEADY_TIME)


async def sleep(node: Node, seconds: float, clock: Clock | None = None) -> None:
    """Suspend the calling coroutine for ``seconds`` (s on ``clock``, default the node clock)."""
    gate = Future()
    timer = node.create_timer(seconds, lambda: gate.done() or gate.set_result(True), clock=clock)
    try:
        await until(gate)
    finally:
        node.destroy_timer(timer)


async def wait_for(node: Node, future: Future, timeout: float, clock: Clock | None = None) -> bool:
    """Await ``future`` for at most ``timeout`` s (on ``clock``, default the node clock); True when done."""
    if future.done():
        return True
    gate = Future()
    future.add_done_callback(lambda _f: gate.done() or gate.set_result(True))
    timer = node.create_timer(timeout, lambda: gate.done() or gate.set_result(False), clock=clock)
    try:
        return bool(await until(gate))
    finally:
        node.destroy_timer(timer)


def first_of(*futures: Future) -> Future:
    """A future that completes with the first of ``futures`` to complete (its result is that future)."""
    gate = Future()

    def settle(done: Any) -> None:
        if not gate.done():
            gate.set_result(done)

    for future in futures:
        future.add_done_callback(settle)
    return gate


class Serializer:
    """Runs coroutines one at a time, in the order they asked.

    Why: on rclpy's Python executors a MutuallyExclusiveCallbackGroup kept a coroutine callback's
    group busy until it returned, so two lifecycle commands never interleaved. The EventsExecutor
    runs every callback on one thread but resumes coroutines as their futures complete, so two
    commands awaiting service answers would interleave; this keeps them in sequence.
    """

    def __init__(self) -> None:
        self._tail: Future | None = None
        self._running = 0

    @property
    def busy(self) -> bool:
        """True while a coroutine runs or waits its turn."""
        return self._running > 0

    async def run(self, make_coroutine: Any) -> Any:
        """Await ``make_coroutine()`` after every coroutine that asked before; its result."""
        previous, mine = self._tail, Future()
        self._tail = mine
        self._running += 1
        try:
            if previous is not None and not previous.done():
                await until(previous)
            return await make_coroutine()
        finally:
            self._running -= 1
            mine.set_result(None)
