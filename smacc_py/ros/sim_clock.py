"""``SimClockLeader``: a /clock for a machine that runs alone on sim time, as fast as it keeps up.

Why: a machine whose states last minutes (sm_atomic_24hr: 500 s each) is tested and benchmarked on
sim time, and there is no simulator to publish /clock. This leader plays the simulator's part of
lockstep (``ros_tools.runtime.lockstep``): it publishes /clock in fixed steps and never runs more than
``max_lead_s`` of sim time ahead of what the machine's ``LockstepParticipant`` (every ``SmaccRuntime``
under ``use_sim_time`` has one, named after the machine) reported as processed. So every step reaches
the machine in order, its timers fire at each step they are due, and the run goes as fast as the
machine (not the leader's guess of it) allows.

The default lead is one step: the next /clock goes out once the machine has processed the last one.
A longer lead saves round trips, but the machine then takes several /clock messages in one go, and
its timers drift: with rclpy's EventsExecutor, sm_atomic's 5-tick countdowns of a 1 s timer lasted
7 to 10 s of sim time with a 1 s lead (0.05 s steps), 5.0 to 5.2 s with 0.2 s, exactly 5 s with one
step (the periodic timers' guard resets a timer it finds early, moving its grid).

The leader is driven by its owner's loop (a test's or a benchmark's main thread); it blocks nothing
that is a callback. Before the machine's first report it re-sends the current time every
``RESEND_WALL_S`` (the runtime enters its initial state on the first /clock it hears, and joins
lockstep only once DDS discovery has settled).

Either executor will do. With rclpy's EventsExecutor holding the timers, a machine driven this way
used to stall (its executor queue growing by about 1 MiB per wall second with dispatches of one due
timer, no more reports); sim-time timers are now called by the clock itself
(ros_tools/runtime/clock_timers.py): bench_sm_atomic_24hr --executor events, 2 sim hours, 0 stalls
(17 "executor behind" warnings in the first hour before).
"""

from __future__ import annotations

import time
from collections.abc import Callable

from rclpy.executors import Executor
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header

from ros_tools.runtime.lockstep import CLOCK_QOS, CLOCK_TOPIC, PROGRESS_QOS, PROGRESS_TOPIC, role_of

RESEND_WALL_S = 0.1  # wall s between re-sends of the current time while the machine has not caught up
NS_PER_S = 1_000_000_000


class SimClockLeader:
    """Publishes /clock on ``node`` in steps of ``step_s``, at most ``max_lead_s`` ahead of ``role``.

    Args:
        node: a node of the caller's (the leader adds one publisher and one subscription).
        role: the participant to follow: the machine's class name (``SmAtomic24Hr``).
        step_s: sim s per /clock message; at most the machine's smallest timer period, so no timer
            skips a due call (the runtime's polling runs at 20 Hz: 0.05 s).
        max_lead_s: sim s the clock may run ahead of the machine's last report; None: one step.
        start_s: the first sim time published (> 0: a zero time reads as "no clock yet").
    """

    def __init__(self, node: Node, role: str, step_s: float = 0.05, max_lead_s: float | None = None,
                 start_s: float = 1.0) -> None:
        max_lead_s = step_s if max_lead_s is None else max_lead_s
        if not (step_s > 0.0 and max_lead_s >= step_s and start_s > 0.0):
            raise ValueError(f"SimClockLeader: need step_s > 0, max_lead_s >= step_s and start_s > 0, got "
                             f"{step_s}, {max_lead_s}, {start_s}")
        self.role = role
        self.step_ns = round(step_s * NS_PER_S)
        self.max_lead_ns = round(max_lead_s * NS_PER_S)
        self.now_ns = round(start_s * NS_PER_S)
        self.start_ns = self.now_ns
        #: the machine's last report (ns of sim time); -1 before the first one
        self.reported_ns = -1
        self.steps = 0  # /clock messages with a new time, since construction
        self._sent_at = 0.0  # time.monotonic() of the last publication
        self._pub = node.create_publisher(Clock, CLOCK_TOPIC, CLOCK_QOS)
        self._sub = node.create_subscription(Header, PROGRESS_TOPIC, self._on_progress, PROGRESS_QOS)
        self._node = node

    @property
    def now_s(self) -> float:
        """The sim time last published (s)."""
        return self.now_ns / NS_PER_S

    @property
    def elapsed_s(self) -> float:
        """Sim s published since ``start_s``."""
        return (self.now_ns - self.start_ns) / NS_PER_S

    def _on_progress(self, msg: Header) -> None:
        if role_of(msg.frame_id) != self.role:
            return
        stamp = msg.stamp.sec * NS_PER_S + msg.stamp.nanosec
        if stamp > 0:
            self.reported_ns = max(self.reported_ns, stamp)

    def _publish(self) -> None:
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = divmod(self.now_ns, NS_PER_S)
        self._pub.publish(msg)
        self._sent_at = time.monotonic()

    def advance(self) -> int:
        """Publish every step the lead allows now (or re-send the current time when it allows none and
        RESEND_WALL_S passed); returns the number of new steps published."""
        if self.reported_ns < 0 or self.now_ns + self.step_ns > self.reported_ns + self.max_lead_ns:
            if time.monotonic() - self._sent_at >= RESEND_WALL_S:
                self._publish()
            return 0
        published = 0
        while self.now_ns + self.step_ns <= self.reported_ns + self.max_lead_ns:
            self.now_ns += self.step_ns
            self._publish()
            published += 1
        self.steps += published
        return published

    def run(self, executor: Executor, until: Callable[[], bool], wall_timeout_s: float,
            spin_s: float = 0.001) -> bool:
        """Advance and spin ``executor`` (which holds this leader's node) until ``until()``; False when
        ``wall_timeout_s`` passed first."""
        deadline = time.monotonic() + wall_timeout_s
        while not until():
            if time.monotonic() > deadline:
                return False
            self.advance()
            executor.spin_once(timeout_sec=spin_s)
        return True

    def destroy(self) -> None:
        """Destroy the publisher and the subscription."""
        self._node.destroy_subscription(self._sub)
        self._node.destroy_publisher(self._pub)
