"""Periodic timers on a sim-time clock, called by the clock itself as /clock moves it.

Why not rclpy's timers: under sim time, rclpy's EventsExecutor (7.1, experimental upstream) runs a
timer through a manager that wakes on every clock jump and queues one dispatch per wake-up while the
timer is due. Measured in this suite: 20 to 75 % of the deliveries came before their time (a dispatch
queued twice moves rcl's next call a period on each time); a state machine's 20 Hz timer, on a clock
that pauses between lockstep steps, fed a queue that grew by 1 MiB per wall second until its executor
ran nothing else for seconds (bench_sm_atomic_24hr --executor events, 2026-11-29, py-spy: the thread
inside the timer's callback, dispatch after dispatch); and CI saw due timers never dispatched at all
(a state machine's spin turned 280 of 180 degrees). rclcpp has the same gap (ros2/rclcpp#2457: its
TimersManager "does not support simulation clock").

Here a timer is a slot on a grid of its clock, and the clock's jump callback makes the calls: when
the node's TimeSource sets the clock to T (inside its /clock subscription's callback, on the thread
that runs the node's callbacks), every timer of that clock due at or before T runs there and then,
oldest slot first, before anything else the executor has queued. The grid and the catch-up rule are
rcl's (rcl_timer_call): a call moves the next slot one period on, and a timer left behind by more than
that skips to the first slot ahead. A backward jump restarts the grid one period after the new time,
as rcl does. No executor is involved, so none can lose, repeat or reorder a call.

Used by ``ros_tools.runtime.timers.create_periodic_timer`` when the clock runs on active ROS time;
a wall or steady clock still gets an rclpy timer. If ROS time is switched off while a timer lives
(``use_sim_time`` set false at run time), the clock stops jumping and the timer stops: it says so.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

from rclpy.clock import Clock, ClockChange, JumpHandle, JumpThreshold, TimeJump
from rclpy.duration import Duration
from rclpy.node import Node

_THRESHOLD = JumpThreshold(min_forward=Duration(nanoseconds=1), min_backward=Duration(nanoseconds=-1),
                           on_clock_change=True)
_ORDER = itertools.count()  # creation order: ties between slots of one time go to the older timer
_DRIVER_ATTRIBUTE = "_navsuite_clock_driver"  # where a clock keeps its _ClockDriver


class ClockTimer:
    """A periodic timer called by its clock's jumps (see the module docstring).

    The methods the suite uses on rclpy's Timer: ``cancel``, ``reset``, ``is_canceled``,
    ``time_until_next_call`` (ns), ``timer_period_ns``, ``clock``; ``destroy`` ends it for good
    (``NavLifecycleNode.destroy_timer`` and ``timers.destroy_periodic_timer`` call it).
    """

    def __init__(self, node: Node, clock: Clock, period_ns: int, callback: Callable[[], None],
                 after_call: Callable[[], None]) -> None:
        if period_ns <= 0:
            raise ValueError(f"a periodic timer needs a period > 0 ns, got {period_ns}")
        self.node = node
        self.clock = clock
        self.callback = callback
        self.timer_period_ns = period_ns
        self._after_call = after_call
        self._order = next(_ORDER)
        self._next_ns = clock.now().nanoseconds + period_ns
        self._canceled = False
        self._destroyed = False
        _ClockDriver.of(clock).add(self)

    # rclpy Timer's API --------------------------------------------------------------------------
    def cancel(self) -> None:
        self._canceled = True

    def is_canceled(self) -> bool:
        return self._canceled

    def reset(self) -> None:
        """Start again one period from now (rcl_timer_reset), also after ``cancel``."""
        if not self._destroyed:
            self._canceled = False
            self._next_ns = self.clock.now().nanoseconds + self.timer_period_ns

    def time_until_next_call(self) -> int | None:
        """ns until the next slot (0 or less: due); None when canceled or destroyed."""
        if self._canceled or self._destroyed:
            return None
        return self._next_ns - self.clock.now().nanoseconds

    def destroy(self) -> None:
        self._destroyed = self._canceled = True
        _ClockDriver.of(self.clock).remove(self)

    # what timers.py's registry asks of a sim-time timer -----------------------------------------------
    def next_call_ns(self) -> int | None:
        """The clock time (ns) of the call owed next; None when canceled, destroyed or its node is."""
        if self._canceled or self._destroyed or not _node_alive(self.node):
            return None
        return self._next_ns

    def due_by_its_clock(self) -> bool:
        ahead = self.time_until_next_call()
        return ahead is not None and ahead <= 0

    def run_missed(self) -> bool:
        """Make the call due by this timer's clock now, if any (the clock's jump normally has)."""
        return self._call_if_due(self.clock.now().nanoseconds)

    # the clock's side ----------------------------------------------------------------------------------
    def _call_if_due(self, now_ns: int) -> bool:
        if self._canceled or self._destroyed or self._next_ns > now_ns:
            return False
        next_ns = self._next_ns + self.timer_period_ns  # rcl_timer_call: one period on, then catch up
        if next_ns < now_ns:
            behind = now_ns - next_ns
            next_ns += (1 + (behind - 1) // self.timer_period_ns) * self.timer_period_ns
        self._next_ns = next_ns
        self.callback()
        return True

    def _restart(self, now_ns: int) -> None:
        self._next_ns = now_ns + self.timer_period_ns


class _ClockDriver:
    """The jump callback of one clock, and the timers it calls.

    The driver lives on its clock (an attribute), not in a registry of this module: a registry kept
    every clock, timer and node it had seen alive, and with them their nodes' DDS participants. A
    node's clock stops jumping when the node is destroyed, so its timers were never pruned; a test
    worker collected about thirty participants, and localhost discovery then stopped finding new
    processes (CI runs 18 and 19: a stack's nav2 never heard /clock). Now clock, driver, timers and
    node form one cycle that the garbage collector frees with the node. rclpy's clock keeps only a
    borrowed pointer to the jump handle, which is why the driver holds it.
    """

    def __init__(self, clock: Clock) -> None:
        self.clock = clock
        self.timers: list[ClockTimer] = []
        self._handle: JumpHandle | None = None

    @classmethod
    def of(cls, clock: Clock) -> _ClockDriver:
        driver: _ClockDriver | None = getattr(clock, _DRIVER_ATTRIBUTE, None)
        if driver is None:
            driver = cls(clock)
            setattr(clock, _DRIVER_ATTRIBUTE, driver)
        return driver

    def add(self, timer: ClockTimer) -> None:
        for gone in [t for t in self.timers if not _node_alive(t.node)]:  # a destroyed node owes nothing
            gone.destroy()
        self.timers.append(timer)
        if self._handle is None:
            self._handle = self.clock.create_jump_callback(_THRESHOLD, post_callback=self._on_jump)

    def remove(self, timer: ClockTimer) -> None:
        if timer in self.timers:
            self.timers.remove(timer)
        if not self.timers and self._handle is not None:
            self._handle.unregister()
            self._handle = None

    def _on_jump(self, jump: TimeJump) -> None:
        now_ns = self.clock.now().nanoseconds
        if jump.clock_change == ClockChange.ROS_TIME_DEACTIVATED:
            for timer in self.timers:
                timer.node.get_logger().error(
                    "use_sim_time was switched off: a periodic sim-time timer "
                    f"({getattr(timer.callback, '__name__', 'callback')}) stops; make it again")
            return
        if jump.delta.nanoseconds < 0 or jump.clock_change == ClockChange.ROS_TIME_ACTIVATED:
            for timer in self.timers:
                timer._restart(now_ns)
            return
        for timer in [t for t in self.timers if not _node_alive(t.node)]:  # its node was destroyed
            timer.destroy()
        due = sorted((t for t in self.timers if t.due_by_its_clock()), key=lambda t: (t._next_ns, t._order))
        called: ClockTimer | None = None
        for timer in due:  # a callback may cancel or destroy a later timer of the same tick: it checks
            while timer._call_if_due(now_ns):
                called = timer
        if called is not None:
            called._after_call()  # once per tick: the lockstep participant may report now


def _node_alive(node: Node) -> bool:
    """False once ``destroy_node`` ran (its handle is gone): its timers owe nothing any more."""
    try:
        with node.handle:
            return True
    except Exception:  # rclpy's InvalidHandle
        return False
