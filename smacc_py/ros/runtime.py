"""``SmaccRuntime``: runs a smacc_py machine on a ROS 2 node, like ``smacc2::run<SmType>()``.

One thread does everything: the thread that spins the executor (``spin()``, or the one thread of
``spin_in_background()``) runs every ROS callback, every event dispatch (transitions, state and
behavior hooks; see ``dispatch.py``) and the ISmaccUpdatable polling, which a node-clock timer at
``signal_detector_loop_freq`` (20 Hz) runs directly. No callback waits for another thread, so the
order of everything follows the order of the executor's callbacks, not the load of the machine.
The only other threads are those of SmaccAsyncClientBehavior's ``on_entry`` (SMACC2's semantics
for user code), whose posts reach the executor thread through ``executor.create_task``, and an
``ExecutorWatch`` that says when the executor falls behind (ros_tools/runtime/executor_watch.py).

The executor is rclpy's C++ EventsExecutor by default (``executor="single"`` or
``NAVSUITE_EXECUTOR=single`` falls back to the SingleThreadedExecutor; see
``ros_tools.runtime.executor``). The node is named after the machine class (``SmNav2Test1``) and
the engine's clock reads the node clock, so ``use_sim_time:=true`` puts the whole machine (timers,
timeouts, transition stamps) on /clock; the initial state is entered right after the first /clock
(``clock_gate.py``), and the process takes part in lockstep simulation (a ``LockstepParticipant``
named after the machine, reporting once ``start()`` was called and DISCOVERY_SETTLE_S have passed since
the runtime was built).

Parameters: ``signal_detector_loop_freq`` (Hz) and ``run_mode`` (debug|release: release publishes
status only periodically and no event log), plus whatever the machine and its clients declare.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from rclpy.context import Context
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter

from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.executor_watch import ExecutorWatch
from ros_tools.runtime.lockstep import LockstepParticipant, uses_sim_time
from ros_tools.runtime.timers import create_periodic_timer, destroy_periodic_timer
from smacc_py.core import SmaccEngineParams, SmaccError, SmaccStateMachineBase
from smacc_py.ros.clock_gate import FirstClock
from smacc_py.ros.context import RosContext, attach_ros_context
from smacc_py.ros.dispatch import ExecutorDispatch
from smacc_py.ros.introspection import IntrospectionPublisher
from smacc_py.ros.params import declare_dataclass_params

_log = logging.getLogger("smacc_py")

RUN_MODES = ("debug", "release")
SPIN_WAKE_S = 0.5  # wall s: longest a spin_once waits, so spin() notices shutdown() without a wake-up
#: wall s between building the runtime and joining lockstep. DDS discovers the machine's subscriptions
#: and action clients (made when the runtime is built) in wall time: 0.05 to 1.6 s on localhost with a
#: stack running (measured on the seed mission); a simulator already stepping at 10x would spend
#: seconds of sim time in StAllSensorsGo meanwhile, a different number on every run. A runtime built
#: while the stack comes up (the demos do) has settled by the time it starts.
DISCOVERY_SETTLE_S = 1.0
STOP_WAIT_S = 10.0  # wall s shutdown() waits for the executor thread to stop the machine


@dataclass(frozen=True)
class RuntimeParams:
    """ROS parameters of the runtime (names are SMACC2's).

    Attributes:
        signal_detector_loop_freq: rate (Hz, node clock) of the ISmaccUpdatable polling loop.
        run_mode: ``debug`` publishes status on every state change and the event log; ``release``
            publishes status every 0.5 s only.
    """

    signal_detector_loop_freq: float = 20.0
    run_mode: str = "debug"

    def __post_init__(self) -> None:
        if not self.signal_detector_loop_freq > 0.0:
            raise ValueError(
                f"signal_detector_loop_freq must be > 0 Hz, got {self.signal_detector_loop_freq!r}"
            )
        if self.run_mode not in RUN_MODES:
            raise ValueError(f"run_mode must be one of {', '.join(RUN_MODES)}, got {self.run_mode!r}")


class SmaccRuntime:
    """Owns the node, the executor and the machine; ``start()`` then ``spin()`` (or ``spin_in_background``).

    Args:
        sm_type: the machine class; it is built as ``sm_type(params=..., now=..., **sm_kwargs)``.
        context: the rclpy context (tests give each runtime its own).
        parameter_overrides: node parameters that win over ``--params-file`` values.
        executor: ``events`` or ``single``; None takes ``$NAVSUITE_EXECUTOR``, else ``events``.
        sm_kwargs: more keyword arguments for the machine's constructor.
    """

    def __init__(
        self,
        sm_type: type[SmaccStateMachineBase],
        *,
        context: Context | None = None,
        parameter_overrides: Sequence[Parameter] | None = None,
        executor: str | None = None,
        sm_kwargs: dict[str, Any] | None = None,
    ) -> None:
        self.node = Node(
            sm_type.__name__, context=context, parameter_overrides=list(parameter_overrides or [])
        )
        try:
            self._build(sm_type, context, executor, sm_kwargs or {})
        except BaseException:  # bad parameters or executor kind: leave no node behind
            self.node.destroy_node()
            raise

    def _build(self, sm_type: type[SmaccStateMachineBase], context: Context | None, executor: str | None,
               sm_kwargs: dict[str, Any]) -> None:
        self.params = declare_dataclass_params(self.node, RuntimeParams)
        engine = SmaccEngineParams(signal_detector_loop_freq=self.params.signal_detector_loop_freq)
        self.ros = RosContext(self.node)
        self.sm = sm_type(params=engine, now=self.ros.now_s, **sm_kwargs)  # type: ignore[call-arg]
        self.sm.set_logger(self.node.get_logger())  # SMACC2's getLogger() is the node's logger
        attach_ros_context(self.sm, self.ros)
        self.sm.initialize()
        self.introspection = IntrospectionPublisher(
            self.node, self.sm, release_mode=self.params.run_mode == "release"
        )
        self.sm.add_observer(self.introspection)
        self.executor = make_executor(executor, context)
        self.executor.add_node(self.node)
        self.dispatch = ExecutorDispatch(self.sm, self.executor)
        self.watch = ExecutorWatch(self.executor, self.sm.name, self.node.get_logger())
        self._first_clock = FirstClock(self.node, self.executor, self._enter_initial_state)
        self._built_at = time.monotonic()  # DDS discovery of the machine's entities starts here
        self._start_requested_at: float | None = None  # time.monotonic() of start()
        self.participant: LockstepParticipant | None = None
        if uses_sim_time(self.node):
            # Ready shortly after start(): the simulator may then step, and its first /clock enters
            # the initial state. (Waiting for the initial state would deadlock a simulator that
            # holds its clock at 0 until this role joins.)
            self.participant = LockstepParticipant(self.node, role=self.sm.name,
                                                   ready=self._discovery_settled)
            self.ros.participant = self.participant
        self._timer: Any = None
        self._stopping = False
        self._stop_requested = False  # request_stop(): spin() returns at its next turn
        self._shut_down = False
        self._spin_thread: int | None = None  # ident of the thread inside spin(), None when none is
        self._spinner: threading.Thread | None = None
        self.started_at_s: float | None = None  # node clock (s) when the machine entered its initial state

    # ------------------------------------------------------------------ lifecycle
    def start(self) -> None:
        """Enter the initial state on the executor thread once the node clock is valid (under
        ``use_sim_time``: right after the first /clock message). Callable from any thread, before or
        after spinning starts; returns at once."""
        if self._shut_down:
            raise SmaccError(f"{self.sm.name}: start() after shutdown()")
        self._start_requested_at = time.monotonic()
        self._first_clock.arm()

    def _discovery_settled(self) -> bool:
        """Lockstep readiness: ``start()`` was called, and the runtime was built DISCOVERY_SETTLE_S
        (wall) ago."""
        return (self._start_requested_at is not None
                and time.monotonic() - self._built_at >= DISCOVERY_SETTLE_S)

    def _enter_initial_state(self) -> None:
        if self._stopping:
            return
        self.started_at_s = self.ros.now_s()
        self.dispatch.dispatch_after(self.sm.start)
        self._timer = create_periodic_timer(self.node, 1.0 / self.params.signal_detector_loop_freq,
                                            self._on_tick)

    def _on_tick(self) -> None:
        """ISmaccUpdatable polling (SMACC2's SignalDetector), then the events it posted."""
        if self.sm.is_running:
            self.dispatch.dispatch_after(self.sm.update)

    def spin(self) -> None:
        """Run the executor in this thread until the context shuts down, ``shutdown()`` or Ctrl-C.

        A callback that raises is logged with its traceback and spinning goes on: rclpy's executors
        let the exception out of ``spin_once``, and in a background thread that would silently freeze
        the machine (its clock stops with /clock, so even its timeouts never fire). The loop calls
        ``spin_once`` with a timeout rather than ``spin()``: this rclpy's EventsExecutor.spin() polls
        without sleeping (half a core when idle) and starves ``create_task`` from other threads.
        """
        self._spin_thread = self.watch.spinning_thread = threading.get_ident()
        self.watch.start()
        try:
            while not self._stopping and not self._stop_requested and self.executor.context.ok():
                try:
                    self.executor.spin_once(timeout_sec=SPIN_WAKE_S)
                except (KeyboardInterrupt, ExternalShutdownException):
                    return
                except Exception:
                    if self._stopping or not self.executor.context.ok():
                        return
                    _log.exception("%s: a callback raised; the executor keeps spinning", self.sm.name)
        finally:
            self._spin_thread = self.watch.spinning_thread = None
            self.watch.stop()

    def request_stop(self) -> None:
        """Make ``spin()`` return after the executor turn in progress (at most SPIN_WAKE_S); safe from a
        signal handler, as it only sets a flag. ``shutdown()`` then stops the machine."""
        self._stop_requested = True

    def spin_in_background(self) -> None:
        """Spin the executor in one daemon thread: the only thread that runs callbacks and dispatch."""
        if self._spinner is not None:
            raise SmaccError(f"{self.sm.name}: the executor already spins in the background")
        self._spinner = threading.Thread(target=self.spin, name=f"{self.sm.name}.executor", daemon=True)
        self._spinner.start()

    # ------------------------------------------------------------------ teardown
    def shutdown(self) -> None:
        """Stop the machine (behaviors' on_exit run: goals cancelled, twists zeroed) on the executor
        thread, stop spinning, then destroy the timer, introspection, the lockstep participant, the
        ROS context's entities, the action clients and the node. Safe to call more than once."""
        if self._shut_down:
            return
        self._shut_down = True
        self._on_executor_thread(self._stop_machine)
        self._stopping = True
        self.dispatch.close()
        self.executor.wake()
        if self._spinner is not None and self._spinner is not threading.current_thread():
            self._spinner.join(2.0 * SPIN_WAKE_S + 1.0)
        self.sm.remove_observer(self.introspection)
        if self.participant is not None and self.node.context.ok():  # else nobody can hear it leave
            self.participant.destroy()
        self.introspection.destroy()
        self.executor.shutdown()
        self.ros.destroy()
        self._destroy_waitables()
        self.node.destroy_node()

    def _stop_machine(self) -> None:
        self._first_clock.close()
        if self._timer is not None:
            destroy_periodic_timer(self.node, self._timer)
            self._timer = None
        if self.sm.is_running:
            self.sm.stop()

    def _on_executor_thread(self, work: Callable[[], None]) -> None:
        """Run ``work`` on the spinning thread and wait for it; directly when nothing spins elsewhere."""
        spinning = self._spin_thread
        if spinning is None or spinning == threading.get_ident():
            work()
            return
        done = threading.Event()

        def task() -> None:
            try:
                work()
            finally:
                done.set()

        self.executor.create_task(task)
        waited = 0.0
        while not done.wait(0.05):
            waited += 0.05
            if self._spin_thread is None and not done.is_set():  # spinning ended: the task never runs
                work()
                return
            if waited > STOP_WAIT_S:
                _log.error("%s: the executor thread did not stop the machine within %.0f s; tearing down "
                           "anyway", self.sm.name, STOP_WAIT_S)
                return

    def _destroy_waitables(self) -> None:
        """Destroy what ``destroy_node`` leaves: action clients and other waitables."""
        for waitable in list(getattr(self.node, "waitables", [])):
            destroy = getattr(waitable, "destroy", None)
            if destroy is not None:
                try:
                    destroy()
                except Exception:  # already destroyed by its owner
                    _log.debug("%s: a waitable was already destroyed", self.sm.name)
