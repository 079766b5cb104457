"""Periodic timers that run once per period, whatever the executor queues.

On sim time (a clock on active ROS time) a periodic timer is a :class:`ClockTimer`, called by its
clock as /clock moves it and held by no executor (ros_tools/runtime/clock_timers.py says why). On
any other clock it is an rclpy timer with the guard below.

Why a guard: rclpy's EventsExecutor (7.1, experimental upstream) queues a timer's "ready" event again
while the first one waits for the executor; rclcpp's EventsExecutor has the same fault
(ros2/rclcpp#2771, a burst of queued timer events). Every delivery runs the callback, and rcl moves
the timer's next call one period on each time without checking that the timer was due. Measured
on the seed mission in lockstep: 20 to 25 % of the deliveries of the controller's, the behavior
tree's and the state machine's timers came before their time, most of them at the same sim time
as the call before (so a cycle ran twice and the next was skipped). Once, the controller server's
20 Hz cycle ran 190 times at one sim time (16.21 s) and stamped its commands up to 25.6 s; its
progress checker, reading those cycle times, aborted the path ("moved less than 0.5 m in 10 s"),
and the simulator drove the robot on the queued commands for 9 s of sim time.

The guard: after a due call the next call lies at most one period ahead of the clock. A delivery
that leaves it further ahead came before its time. It is dropped and the timer is reset, so the
next call is one period after now instead of one period later for every such delivery. (Putting
the next call back exactly on the old grid, by resetting with a shortened period, made the
executor deliver the event again at once, hundreds of times until the clock moved on.)

Lockstep order (docs/architecture.md, "What repeats"): a process may tell the simulator it has done
tick T only once every timer due at or before T has run. :func:`earliest_due_ns` gives the oldest
slot a sim-time timer of this process still owes, and :func:`add_after_call` lets the lockstep
participant (ros_tools/runtime/lockstep.py) send the report it withheld as soon as that timer ran.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Any

from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.node import Node

from ros_tools.runtime.clock_timers import ClockTimer

#: this process's timers on the ROS clock (sim time under /clock): the ones a lockstep tick waits for
_SIM_TIMERS: weakref.WeakSet[_DueOnly | ClockTimer] = weakref.WeakSet()
#: called after every delivery of such a timer (due or dropped): the lockstep participant's wake-up
_AFTER_CALL: list[Callable[[], None]] = []


class _DueOnly:
    """The timer callback: runs ``callback`` for due deliveries, drops and counts the early ones."""

    def __init__(self, node: Node, callback: Callable[[], None]) -> None:
        self.node = node
        self.callback = callback
        self.timer: Any = None
        self.dropped = 0  # deliveries before their time, since the timer was made

    def __call__(self) -> None:
        timer = self.timer
        ahead = timer.time_until_next_call()  # ns; None once canceled
        if ahead is None:
            return
        if ahead > timer.timer_period_ns:
            timer.reset()  # next call one period from now
            self.dropped += 1
            self.node.get_logger().debug(
                f"dropped a timer event before its time ({getattr(self.callback, '__name__', 'callback')}, "
                f"{self.dropped} so far)", throttle_duration_sec=10.0)
        else:
            self.callback()
        _run_after_call_hooks()

    def run_missed(self) -> bool:
        """Make the call the executor owes now, as its dispatch would (rcl takes the call, moving the
        next one a period on; then the callback runs); False when canceled or destroyed.

        For the lockstep participant only (:func:`run_overdue`); the after-call hooks do not run (the
        participant that called this reports next). A dispatch the executor still had queued then
        finds the timer a period ahead and is dropped as early (``__call__``).
        """
        timer = self.timer
        try:
            with timer.handle:
                if timer.handle.is_timer_canceled():
                    return False
                timer.handle.call_timer()
        except Exception:  # destroyed with its node (InvalidHandle): nothing owed any more
            return False
        self.callback()
        return True

    def due_by_its_clock(self) -> bool:
        """Whether the timer's own clock has reached its next call (a node clock may still lag the
        newest /clock the participant heard: then the executor will dispatch it once it moves)."""
        try:
            ahead = self.timer.time_until_next_call()
        except Exception:  # destroyed with its node
            return False
        return ahead is not None and ahead <= 0

    def next_call_ns(self) -> int | None:
        """The clock time (ns) of the call this timer owes next; None when canceled or destroyed."""
        timer = self.timer
        try:
            ahead = timer.time_until_next_call()
            return None if ahead is None else int(timer.clock.now().nanoseconds + ahead)
        except Exception:  # destroyed with its node (InvalidHandle): it owes nothing any more
            return None


def create_periodic_timer(node: Node, period_s: float, callback: Callable[[], None],
                          clock: Clock | None = None) -> Any:
    """A timer calling ``callback`` every ``period_s`` s of ``clock`` (default: the node's clock).

    On a clock running on active ROS time (sim time), a :class:`ClockTimer` that the clock's jumps
    call (ros_tools/runtime/clock_timers.py says why no executor does); otherwise
    ``node.create_timer`` with the deliveries that come before their time dropped (see the module
    docstring). ``callback`` must be a plain function. End it with :func:`destroy_periodic_timer`
    (``NavLifecycleNode.destroy_timer`` does) or ``cancel()``.
    """
    clock = clock if clock is not None else node.get_clock()
    if clock.clock_type == ClockType.ROS_TIME and getattr(clock, "ros_time_is_active", False):
        timer = ClockTimer(node, clock, round(period_s * 1e9), callback, _run_after_call_hooks)
        _SIM_TIMERS.add(timer)
        return timer
    due_only = _DueOnly(node, callback)
    due_only.timer = node.create_timer(period_s, due_only, clock=clock)
    if due_only.timer.clock.clock_type == ClockType.ROS_TIME:
        _SIM_TIMERS.add(due_only)
    return due_only.timer


def destroy_periodic_timer(node: Node, timer: Any) -> None:
    """Destroy a timer made by :func:`create_periodic_timer`, whichever kind it is."""
    if isinstance(timer, ClockTimer):
        timer.destroy()
    else:
        node.destroy_timer(timer)


def _run_after_call_hooks() -> None:
    for hook in list(_AFTER_CALL):
        hook()


def earliest_due_ns(context: Any = None) -> int | None:
    """The oldest call (ns, ROS clock) that a periodic timer of this process (of nodes on ``context``,
    when given) still owes; None if none.

    Why: a lockstep participant that reports tick T before the timer due at T has run lets the
    simulator step on while that cycle is still to come, so the cycle sees data of later steps on one
    run and not on the next (docs/architecture.md, "What repeats"). The participant reports at most
    one nanosecond before this time.
    """
    owing = [t for t in list(_SIM_TIMERS) if context is None or t.node.context is context]
    calls = [call for call in (t.next_call_ns() for t in owing) if call is not None]
    return min(calls, default=None)


def run_overdue(clock_ns: int, context: Any = None) -> list[str]:
    """Run every periodic sim-time timer of this process (of nodes on ``context``, when given) whose
    owed call is due at or before ``clock_ns``; the names of their callbacks, oldest call first.

    Why: rclpy's EventsExecutor sometimes never dispatches a sim-time timer that is due (CI: the
    state machine's 10 Hz spin control stopped for seconds of sim time, the robot turned 280 of 180
    degrees; its signal-detector timer stopped and a demo never left StNavigateToWaypoint1). The
    lockstep participant calls this for a timer its tick has waited for too long, so a missed
    wake-up costs that wait, never the timer. Only a call due by the timer's own clock is made: a
    node clock that lags the participant's /clock (CI: the isolated layout's navigation process)
    is not a missed wake-up, and a call made ahead of it crawled at one call per grace.
    """
    owing = [t for t in list(_SIM_TIMERS) if context is None or t.node.context is context]
    due = sorted(((call, index, t) for index, t in enumerate(owing)
                  if (call := t.next_call_ns()) is not None and call <= clock_ns and t.due_by_its_clock()),
                 key=lambda c: c[:2])
    return [getattr(t.callback, "__name__", "callback") for _, _, t in due if t.run_missed()]


def add_after_call(hook: Callable[[], None]) -> None:
    """Run ``hook()`` after every delivery of a periodic sim-time timer of this process."""
    _AFTER_CALL.append(hook)


def remove_after_call(hook: Callable[[], None]) -> None:
    """Undo :func:`add_after_call` (no error when ``hook`` is not registered)."""
    if hook in _AFTER_CALL:
        _AFTER_CALL.remove(hook)


def nominal_call_ns(node: Node, timer: Any) -> int:
    """The nominal time (ns, the timer's clock) of the call running now: its slot on the timer's grid.

    Why not ``now``: under lockstep the clock may have moved on by a /clock message or two when the
    callback runs, and how far depends on wall timing. The grid is fixed from the timer's creation
    (as long as it is not reset), so cycle times, the stamps of the commands a cycle publishes and
    with them the sim times at which sim2d applies stamped commands are the same on every run.
    Call it from the timer's own callback.
    """
    now = node.get_clock().now().nanoseconds
    return int(now + timer.time_until_next_call() - timer.timer_period_ns)
