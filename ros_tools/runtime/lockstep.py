"""The participant side of lockstep simulation: report the sim time this process has fully processed.

Why: a simulator that runs by the wall clock outruns a loaded stack. The controller then acts on
late poses and the outcome of a mission depends on how busy the machine is. In lockstep the
simulator (sim2d with ``lockstep: true``) never steps more than ``lockstep.max_lead`` s of sim time
(one control period) beyond the slowest participant's report, so the stack sees the same world
at the same sim times however slow the machine is, and the sim runs as fast as the stack keeps up.

Protocol, on topic ``/lockstep/progress`` (std_msgs/Header, reliable, depth 10):

* ``frame_id`` names the participant (``<role>:<pid>``, e.g. ``nav2:4242``); the role is what
  warnings and the simulator's ``lockstep.participants`` list use;
* ``stamp`` is the newest tick T this process has done: its /clock message has been taken off the
  executor's queue (the executor runs callbacks in arrival order and the simulator sends /clock
  after the data of the same time, so every scan, odometry and TF message stamped up to T has been
  processed) and every periodic sim-time timer of the process due at or before T has run. Those
  timers are called by their node's clock as it reaches T (ros_tools/runtime/clock_timers.py), not
  by the executor: left to rclpy's EventsExecutor, a due timer ran after the report on some runs and
  the simulator stepped on meanwhile (docs/architecture.md, "What repeats"), or never ran at all.
  Each node's clock moves on its own /clock subscription, so a node may not have reached T when the
  participant hears it: the report then waits for that node's clock, and goes out once its timers ran;
* a zero ``stamp`` says the participant leaves (the runner sends it at teardown) and no longer
  holds the simulator back.

A participant reports at most every ``report_period`` s of sim time (default 0.02 s, under the
simulator's 0.05 s lead, so the simulator never waits for a report that is not coming), and on
every repeated /clock (the simulator re-sends its time while it waits, once per wall 0.1 s). Until
its ``ready`` predicate is true (e.g. until the lifecycle managers report active) it reports
nothing, and a simulator told to expect its role stays paused. :meth:`LockstepParticipant.hold`
pauses it the same way later on, for a bounded wall time (e.g. while a new subscription is being
discovered).
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from typing import Any

from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header

from ros_tools.runtime import timers

PROGRESS_TOPIC = "/lockstep/progress"
CLOCK_TOPIC = "/clock"
PROGRESS_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
CLOCK_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
REPORT_PERIOD = 0.02  # s of sim time between reports
#: wall s a process may hold the simulator for a request crossing DDS (under lockstep.timeout, 10 s)
REQUEST_HOLD = 2.0
#: wall s a report waits for a node clock that lags its tick before counting the tick done without its calls
OWED_GRACE = 0.25

_PROCESS_PARTICIPANTS: list[LockstepParticipant] = []  # this process's live participants


def participant_name(role: str) -> str:
    """``<role>:<pid>``: unique per process, and the role still reads well in a warning."""
    return f"{role}:{os.getpid()}"


def role_of(name: str) -> str:
    """The role part of a participant name (``nav2:4242`` -> ``nav2``)."""
    return name.rsplit(":", 1)[0]


class LockstepParticipant:
    """Reports this process's progress in sim time on PROGRESS_TOPIC (see the module docstring).

    Args:
        node: any node of the process (the participant adds one subscription and one publisher).
        role: what the process is (``nav2``, ``localization``, ``SmNav2Test1``).
        ready: while it returns False, nothing is reported (checked on every /clock message).
        report_period: s of sim time between reports.
    """

    def __init__(self, node: Node, role: str, ready: Callable[[], bool] | None = None,
                 report_period: float = REPORT_PERIOD) -> None:
        self.node = node
        self.name = participant_name(role)
        self._ready = ready
        self._period_ns = int(report_period * 1e9)
        self._last_clock_ns = -1
        self._last_report_ns = -1
        self._holds: list[tuple[Callable[[], bool], float]] = []  # (until, wall deadline)
        self._holds_lock = threading.Lock()  # hold() may come from another thread than /clock's
        #: orders reports against the leave: destroy() may run on another thread than /clock's
        self._publish_lock = threading.Lock()
        self._pub = node.create_publisher(Header, PROGRESS_TOPIC, PROGRESS_QOS)
        self._sub = node.create_subscription(Clock, CLOCK_TOPIC, self._on_clock, CLOCK_QOS)
        self._left = False
        self._owed = False  # the newest /clock was not fully reported: a hold or a due timer kept it back
        self._owed_since: tuple[int, float] | None = None  # (the owed call's ns, wall s it was first seen)
        timers.add_after_call(self._report_withheld)
        _PROCESS_PARTICIPANTS.append(self)

    @property
    def reported_ns(self) -> int:
        """The last sim time reported (ns), -1 before the first report."""
        return self._last_report_ns

    def _on_clock(self, msg: Clock) -> None:
        if self._left:  # a /clock the executor had queued before the leave
            return
        now = msg.clock.sec * 1_000_000_000 + msg.clock.nanosec
        repeated = now <= self._last_clock_ns  # the simulator re-sends its time while it waits
        self._last_clock_ns = now
        if self._ready is not None:
            if not self._ready():
                return
            self._ready = None  # ready once, ready for good
        if self._holds and self._held():
            self._owed = True
            return
        done = self._done_ns(now)
        self._owed = done < now  # a timer still owes a call at or before this tick
        if done <= self._last_report_ns and not repeated:
            return
        if repeated or self._owed or done >= self._last_report_ns + self._period_ns:
            self._report(done)

    def _done_ns(self, clock_ns: int) -> int:
        """The newest tick (ns) done, given the newest /clock taken off the queue: one ns before the
        oldest call a periodic sim-time timer of this process still owes, when that comes earlier.

        Sim-time timers are called by their node's clock (ros_tools/runtime/clock_timers.py), so a
        call still owed at T means that node's clock has not reached T yet (each node's TimeSource
        has its own /clock subscription). The report waits for it, OWED_GRACE wall seconds at most;
        past that the tick counts as done without it and a warning says so (the simulator re-sends
        /clock every 0.1 s while it waits, so the grace is checked then). A timer the executor runs
        (one on a clock that is not sim time) whose call is due by its own clock is made here
        (timers.run_overdue): rclpy's EventsExecutor misses such wake-ups at times, and a report
        withheld for a call that never came stopped the world (CI run 6).
        """
        timers.run_overdue(clock_ns, self.node.context)
        due = timers.earliest_due_ns(self.node.context)
        if due is None or due > clock_ns:
            self._owed_since = None
            return clock_ns
        wall = time.monotonic()
        if self._owed_since is None or self._owed_since[0] != due:
            self._owed_since = (due, wall)
        elif wall - self._owed_since[1] > OWED_GRACE:
            self.node.get_logger().warning(
                f"lockstep: a timer due at sim time {due * 1e-9:.3f} s has not run {OWED_GRACE} s (wall) "
                "after its tick because its node's clock has not reached it; reporting the tick done "
                "without it", throttle_duration_sec=10.0)
            return clock_ns
        return due - 1

    def hold(self, until: Callable[[], bool], grace: float, wake: Any = None) -> None:
        """Report nothing until ``until()`` is true or ``grace`` wall seconds have passed.

        Why: a subscription made mid-run hears nothing until DDS discovery has matched it, which
        takes wall time; at ``--rtf max`` the simulator would run on by seconds of sim time
        meanwhile, and a sim-time timeout racing that message (a state's 15 s fallback timer against
        the first bond heartbeat) would be decided by the machine's load. Keep ``grace`` under the
        simulator's ``lockstep.timeout`` (10 s), or it drops this participant.

        ``wake``: a future (``add_done_callback``) whose completion releases the hold. The withheld
        report is then sent at once, instead of at the next /clock: a simulator blocked on this
        participant re-sends /clock only every 0.1 s of wall time, and the behavior tree's requests
        (about three per sim second) cost the seed mission 30 % of its speed that way (bench_mission,
        real-time factor 6.0 before the holds, 4.8 with them).
        """
        with self._holds_lock:
            self._holds.append((until, time.monotonic() + grace))
        if wake is not None:
            wake.add_done_callback(lambda _future: self._report_withheld())

    def _report_withheld(self) -> None:
        """Report the newest tick done if a hold or a timer still due kept it back and none does now."""
        clock_ns = self._last_clock_ns
        if (not self._owed or self._left or self._ready is not None or clock_ns <= self._last_report_ns
                or self._held()):
            return
        done = self._done_ns(clock_ns)
        self._owed = done < clock_ns
        if done > self._last_report_ns:
            self._report(done)

    def _held(self) -> bool:
        now = time.monotonic()
        with self._holds_lock:
            self._holds = [(until, deadline) for until, deadline in self._holds
                           if now < deadline and not _released(until)]
            return bool(self._holds)

    def _report(self, now_ns: int) -> None:
        # A zero stamp means "leaving", but the simulator starts at sim time 0 (and holds there while
        # it waits for its expected roles): report 0 as 1 ns so a participant joins instead of leaving.
        now_ns = max(now_ns, 1)
        header = Header(frame_id=self.name)
        header.stamp.sec, header.stamp.nanosec = divmod(now_ns, 1_000_000_000)
        with self._publish_lock:
            if self._left:  # left already: a report now would make the simulator wait again
                return
            self._pub.publish(header)
            self._last_report_ns = now_ns

    def leave(self) -> None:
        """Tell the simulator not to wait for this process any more (a zero stamp).

        After Ctrl-C the context is already shut down and nothing can be sent: the simulator then
        drops this participant once its process is gone (or after ``lockstep.timeout``).

        No report follows the leave, whichever thread is spinning. A /clock callback running on the
        executor's thread while a test's main thread leaves used to send one more report: the
        simulator took the participant back and, once it was destroyed, waited ``lockstep.timeout``
        for a process that was alive (CI run CA: the next test of the module found no ground truth
        for 20 s). The leave does not wait for the simulator's acknowledgement: the sample is on the
        wire when ``publish`` returns (synchronous publication), and Fast DDS acknowledges it only
        at the writer's next heartbeat, so such a wait cost a second per teardown and saved nothing.
        """
        with self._publish_lock:
            self._left = True
        if self.node.context.ok():
            self._pub.publish(Header(frame_id=self.name))

    def destroy(self) -> None:
        """Leave, then destroy the subscription and the publisher."""
        if self in _PROCESS_PARTICIPANTS:
            _PROCESS_PARTICIPANTS.remove(self)
        timers.remove_after_call(self._report_withheld)
        self.leave()
        self.node.destroy_subscription(self._sub)
        self.node.destroy_publisher(self._pub)


def hold_process(until: Callable[[], bool], grace: float = REQUEST_HOLD, wake: Any = None) -> bool:
    """Hold this process's participants (:meth:`LockstepParticipant.hold`); nothing outside lockstep.

    For a request whose answer a sim-time deadline waits for, sent from deep inside a node that does
    not know the participant (a behavior-tree leaf's goal and its ``server_timeout`` in ms of sim
    time): until the answer is back, the simulator does not run on by the wall time the request
    spends in DDS, so the timeout is decided by sim time, not by the machine's load (CI run BJ: a
    loaded run timed out after "1000 ms" waiting for an acknowledgement).

    Returns whether anything holds (False outside lockstep: the simulator, if any, does not wait).
    """
    participants = list(_PROCESS_PARTICIPANTS)
    for participant in participants:
        participant.hold(until, grace, wake)
    return bool(participants)


def clock_heard() -> bool | None:
    """Whether a /clock message reached this process's participants (None: it has none), for a
    process that says what it waits for: a lockstep simulator sends /clock before its first step."""
    if not _PROCESS_PARTICIPANTS:
        return None
    return any(participant._last_clock_ns >= 0 for participant in _PROCESS_PARTICIPANTS)


def _released(until: Callable[[], bool]) -> bool:
    """``until()``, where an error (e.g. the entity it asks was destroyed) also ends the hold: an
    exception here would end this /clock callback, and with it every report of the process."""
    try:
        return bool(until())
    except Exception:  # any failure of a hold condition releases it
        return True


def uses_sim_time(node: Any) -> bool:
    """True when ``node`` has ``use_sim_time`` set (only such processes take part in lockstep)."""
    return bool(node.has_parameter("use_sim_time") and node.get_parameter("use_sim_time").value)
