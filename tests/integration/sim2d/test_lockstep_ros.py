"""sim2d in lockstep over rclpy: never ahead of its participants, released by leaving or silence.

A fake participant in the test reports only when the test tells it to, so the test decides how far
the stack has "processed" and checks what the simulator's /clock does about it.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import pytest

pytest.importorskip("tf2_msgs.msg")

from rclpy.clock import Clock as RosClock
from rclpy.clock_type import ClockType
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header
from std_srvs.srv import SetBool

from navsuite_testing.ros import spin_until
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC, LockstepParticipant, hold_process
from sim2d.ros.sim_node import Sim2dNode

pytestmark = pytest.mark.ros

S = 1_000_000_000                    # ns per s
LEAD = 50_000_000                    # ns: the default lockstep.max_lead (0.05 s)
STEP = 5_000_000                     # ns: the default physics_step (0.005 s)
TIMEOUT = 1.0                        # wall s: lockstep.timeout of the silence tests
FAKE = "fake:1"                      # the fake participant's name (role "fake")
DEEP = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)


@dataclass
class LockstepRig:
    """A Sim2dNode in lockstep at max speed, a fake participant and a /clock recorder on one executor.

    The fake reports only when the test calls :meth:`report`; while ``keepalive`` is on it also
    repeats its last report every 0.1 s of wall time (alive, but no further along), so only the
    test decides when it falls silent (``keepalive`` off). A wall timer rather than an answer to
    each repeated /clock: after a free run, the recorder's /clock backlog can take longer to drain
    than the silence timeout.
    """

    sim: Sim2dNode
    fake: Node
    executor: Executor
    progress: Publisher
    clocks: list[int] = field(default_factory=list)       # every /clock received (ns)
    warnings: list[str] = field(default_factory=list)     # the sim's warning log lines
    keepalive: bool = True
    reported: int | None = None

    def spin_until(self, predicate: Callable[[], bool], what: str, timeout: float = 20.0) -> None:
        spin_until(self.executor, predicate, timeout, what)

    def report(self, time_ns: int, name: str = FAKE) -> None:
        """Report progress as participant ``name`` (0 ns: leave)."""
        header = Header(frame_id=name)
        header.stamp.sec, header.stamp.nanosec = divmod(time_ns, S)
        self.progress.publish(header)
        if name == FAKE:
            self.reported = time_ns or None

    def on_clock(self, msg: Clock) -> None:
        self.clocks.append(msg.clock.sec * S + msg.clock.nanosec)

    def repeat_report(self) -> None:
        if self.keepalive and self.reported is not None:
            self.report(self.reported)

    def spin_for(self, seconds: float) -> None:
        """Serve callbacks for ``seconds`` of wall time: for a test whose subject is time passing
        (silence while paused), never to wait for something to happen."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)

    def newest_clock(self) -> int:
        return max(self.clocks, default=-1)

    def wait_for_repeated_clocks(self, count: int = 3) -> None:
        """Spin until the sim has re-sent the same /clock ``count`` times: it is waiting, not stepping."""
        def repeated() -> bool:
            tail = self.clocks[-count:]
            return len(tail) == count and len(set(tail)) == 1
        self.spin_until(repeated, f"{count} repeated /clock messages (the sim blocked)")

    def wait_blocked_at(self, reported_ns: int) -> int:
        """Wait until the sim blocks after a report; return where it stopped (checked against the bound)."""
        self.spin_until(lambda: self.newest_clock() >= reported_ns + LEAD - STEP, "the sim at its limit")
        self.wait_for_repeated_clocks()
        stopped = self.newest_clock()
        assert reported_ns + LEAD - STEP <= stopped <= reported_ns + LEAD + STEP
        assert self.sim.sim.time_ns <= reported_ns + LEAD + STEP
        return stopped


@contextlib.contextmanager
def lockstep_rig(ros_context: Any, executor_kind: str = "single",
                 **lockstep: Any) -> Iterator[LockstepRig]:
    """The rig with ``lockstep.<name>`` parameters from ``lockstep`` (real-time factor: max)."""
    params = {"real_time_factor": 0.0, "lockstep.enabled": True,
              **{f"lockstep.{name}": value for name, value in lockstep.items()}}
    sim = Sim2dNode(context=ros_context,
                    parameter_overrides=[Parameter(name, value=value) for name, value in params.items()])
    fake = Node("fake_participant", context=ros_context)
    executor = make_executor(executor_kind, context=ros_context)
    rig = LockstepRig(sim, fake, executor, fake.create_publisher(Header, PROGRESS_TOPIC, PROGRESS_QOS))
    fake.create_subscription(Clock, "/clock", rig.on_clock, DEEP)
    fake.create_timer(0.1, rig.repeat_report, clock=RosClock(clock_type=ClockType.STEADY_TIME))
    logger = sim.get_logger()
    logger.warning = lambda message, *args, **kwargs: rig.warnings.append(message)  # type: ignore[method-assign]
    executor.add_node(sim)
    executor.add_node(fake)
    try:
        rig.spin_until(lambda: rig.progress.get_subscription_count() > 0 and bool(rig.clocks),
                       "the sim's progress subscription and its first /clock")
        yield rig
    finally:
        executor.shutdown()
        fake.destroy_node()
        sim.destroy_node()


@pytest.fixture
def rig(ros_context: Any) -> Iterator[LockstepRig]:
    with lockstep_rig(ros_context, participants=["fake"]) as rig:
        yield rig


@pytest.fixture
def short_timeout_rig(ros_context: Any) -> Iterator[LockstepRig]:
    with lockstep_rig(ros_context, participants=["fake"], timeout=TIMEOUT) as rig:
        yield rig


def test_expected_role_holds_the_start_then_the_clock_never_passes_report_plus_lead(rig: LockstepRig) -> None:
    rig.wait_for_repeated_clocks()
    rig.report(2 * S, name="bystander:9")              # a role nobody waits for does not start the sim
    rig.wait_for_repeated_clocks(6)
    assert rig.newest_clock() == 0 and rig.sim.sim.time_ns == 0

    rig.report(100_000_000)                            # the expected role: the sim may go to 0.15 s
    stopped = rig.wait_blocked_at(100_000_000)
    rig.report(300_000_000)                            # advances again after a report
    assert rig.wait_blocked_at(300_000_000) > stopped
    assert not rig.warnings


def test_a_participant_that_leaves_releases_the_sim(rig: LockstepRig) -> None:
    rig.report(100_000_000)
    rig.wait_blocked_at(100_000_000)
    rig.report(0)                                      # zero stamp: leaving
    rig.spin_until(lambda: rig.newest_clock() > 2 * S, "the sim to run on without the participant")
    assert not rig.warnings                            # leaving is not a fault


def test_a_silent_participant_is_dropped_with_one_warning(short_timeout_rig: LockstepRig) -> None:
    rig = short_timeout_rig
    rig.report(100_000_000)
    rig.wait_blocked_at(100_000_000)
    rig.keepalive = False                              # falls silent
    rig.spin_until(lambda: rig.newest_clock() > 2 * S, "the sim to go on without the silent one")
    assert rig.sim.gate is not None and rig.sim.gate.participants == {}
    assert rig.warnings == [f"lockstep: fake ({FAKE}) has not reported for {TIMEOUT} s wall; "
                            "the simulator goes on without it"]
    rig.keepalive = True
    rig.report(rig.sim.sim.time_ns)                    # back: it holds the sim again
    rig.wait_for_repeated_clocks()
    assert len(rig.warnings) == 1 and FAKE in rig.sim.gate.participants


def test_silence_while_paused_does_not_drop_a_participant(short_timeout_rig: LockstepRig) -> None:
    rig = short_timeout_rig
    pause = rig.fake.create_client(SetBool, "/sim2d/pause")
    assert pause.wait_for_service(timeout_sec=10.0)
    rig.report(100_000_000)
    rig.wait_blocked_at(100_000_000)
    future = pause.call_async(SetBool.Request(data=True))
    rig.spin_until(future.done, "pause")
    frozen = rig.sim.sim.time_ns
    rig.keepalive = False                              # nothing to answer while paused anyway
    rig.spin_for(2 * TIMEOUT)                          # twice the timeout passes while paused
    assert rig.sim.gate is not None and FAKE in rig.sim.gate.participants and not rig.warnings
    assert rig.sim.sim.time_ns == frozen
    rig.keepalive = True
    future = pause.call_async(SetBool.Request(data=False))
    rig.spin_until(future.done, "resume")
    rig.report(frozen)
    rig.wait_for_repeated_clocks()
    assert not rig.warnings


def test_the_real_participant_class_keeps_the_sim_going(ros_context: Any) -> None:
    """ros_tools' LockstepParticipant (reports every 0.02 s and on repeated clocks): no deadlock, and
    the role it declares releases a sim that waits for it at time 0. Spun by the EventsExecutor, as
    the sim2d command does by default (the stepping timer is cancelled and reset)."""
    with lockstep_rig(ros_context, "events", participants=["stack"]) as rig:
        participant = LockstepParticipant(rig.fake, "stack")
        rig.spin_until(lambda: rig.newest_clock() > 2 * S, "2 s of sim time in lockstep")
        assert rig.sim.gate is not None and participant.name in rig.sim.gate.participants
        assert rig.sim.sim.time_ns <= participant.reported_ns + LEAD + STEP
        participant.destroy()


def test_a_leave_is_final_however_many_clocks_follow(ros_context: Any) -> None:
    """After leave() the participant reports nothing more, though its subscription still takes
    /clock: one more report would make the simulator take it back and, once it is destroyed, wait
    lockstep.timeout for a process that is alive (a test's main thread leaving while its executor
    thread still handles /clock)."""
    with lockstep_rig(ros_context, "events", participants=["stack"]) as rig:
        participant = LockstepParticipant(rig.fake, "stack")
        rig.spin_until(lambda: rig.newest_clock() > S, "1 s of sim time in lockstep")
        participant.leave()
        left_at = participant.reported_ns
        rig.spin_until(lambda: rig.newest_clock() > left_at + 2 * S, "the sim to run on after the leave")
        assert rig.sim.gate is not None and participant.name not in rig.sim.gate.participants
        assert participant.reported_ns == left_at
        participant.destroy()


def test_a_hold_stops_the_sim_until_its_condition_or_its_grace_runs_out(ros_context: Any) -> None:
    """LockstepParticipant.hold: no report (so no sim time beyond the lead) while the condition is
    false, the sim goes on once it is true; an unmet condition is given up after its grace."""
    with lockstep_rig(ros_context, "events", participants=["stack"]) as rig:
        participant = LockstepParticipant(rig.fake, "stack")
        rig.spin_until(lambda: rig.newest_clock() > S, "1 s of sim time in lockstep")
        released = [False]
        participant.hold(lambda: released[0], grace=30.0)
        held_at = participant.reported_ns
        rig.wait_for_repeated_clocks()  # the sim waits, re-sending its time, and no report comes
        assert participant.reported_ns == held_at
        assert rig.sim.sim.time_ns <= held_at + LEAD + STEP
        released[0] = True
        rig.spin_until(lambda: rig.newest_clock() > held_at + S, "the sim to go on after the release")
        participant.hold(lambda: False, grace=0.3)
        rig.spin_until(lambda: rig.newest_clock() > held_at + 2 * S, "the sim to go on after the grace")

        def broken() -> bool:
            raise RuntimeError("the subscription it asks was destroyed")

        participant.hold(broken, grace=30.0)  # a failing condition releases its hold at once
        rig.spin_until(lambda: rig.newest_clock() > held_at + 3 * S, "the sim to go on past a broken hold")
        participant.destroy()


def test_a_hold_released_by_its_future_reports_the_withheld_time_at_once(ros_context: Any) -> None:
    """hold(..., wake=future): when the request's future completes, the report the hold kept back goes
    out from the future's callback, not at the next /clock (which a blocked simulator re-sends only
    every 0.1 s of wall time: behavior-tree requests cost the seed mission 30 % of its speed)."""
    with lockstep_rig(ros_context, "events", participants=["stack"]) as rig:
        participant = LockstepParticipant(rig.fake, "stack")
        rig.spin_until(lambda: rig.newest_clock() > S, "1 s of sim time in lockstep")
        answer = Future()
        participant.hold(answer.done, grace=30.0, wake=answer)
        held_at = participant.reported_ns
        rig.wait_for_repeated_clocks()  # the sim waits at the lead
        assert participant.reported_ns == held_at
        answer.set_result(True)  # no executor attached: its done callbacks run here and now
        assert participant.reported_ns > held_at  # the newest /clock taken, reported without a new one
        rig.spin_until(lambda: rig.newest_clock() > held_at + S, "the sim to go on after the answer")
        participant.destroy()


def test_hold_process_holds_the_participants_of_this_process_only_while_they_live(ros_context: Any) -> None:
    """hold_process (what a behavior-tree leaf calls while its goal crosses DDS) holds every live
    participant of the process; a destroyed one is no longer held (nor holds anything)."""
    with lockstep_rig(ros_context, "events", participants=["stack"]) as rig:
        participant = LockstepParticipant(rig.fake, "stack")
        rig.spin_until(lambda: rig.newest_clock() > S, "1 s of sim time in lockstep")
        answered = [False]
        hold_process(lambda: answered[0], grace=30.0)
        held_at = participant.reported_ns
        rig.wait_for_repeated_clocks()
        assert participant.reported_ns == held_at and rig.sim.sim.time_ns <= held_at + LEAD + STEP
        answered[0] = True
        rig.spin_until(lambda: rig.newest_clock() > held_at + S, "the sim to go on once answered")
        participant.destroy()
        hold_process(lambda: False, grace=30.0)  # no participant left: nothing to hold
        rig.spin_until(lambda: rig.newest_clock() > held_at + 2 * S, "the sim to run on")


def test_an_expected_role_that_never_reports_is_named_once_and_the_sim_starts(ros_context: Any) -> None:
    with lockstep_rig(ros_context, participants=["absent"], startup_timeout=0.5) as rig:
        rig.spin_until(lambda: rig.newest_clock() > S, "the sim to start without the absent role")
        assert rig.warnings == ["lockstep: absent has not reported within 0.5 s wall "
                                "(lockstep.startup_timeout); the simulator goes on without it"]
