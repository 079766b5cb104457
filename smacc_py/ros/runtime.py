"""``SmaccRuntime``: runs a smacc_py machine on a ROS 2 node, like ``smacc2::run<SmType>()``.

Threads and who does what:

* the engine's own worker thread processes events (run to completion, one at a time);
* a MultiThreadedExecutor runs every ROS callback; callbacks only translate messages and post events,
  so none of them ever waits for the machine;
* the SignalDetector thread calls ``sm.update()`` (ISmaccUpdatable polling) each time a node-clock timer
  at ``signal_detector_loop_freq`` (20 Hz) ticks; the timer callback only sets a flag, so a transition
  holding the machine lock delays the polling thread, never an executor thread.

The node is named after the machine class (``SmNav2Test1``) and the engine's clock reads the node
clock, so ``use_sim_time:=true`` puts the whole machine (timers, timeouts, transition stamps) on /clock.
Parameters: ``signal_detector_loop_freq`` (Hz) and ``run_mode`` (debug|release: release publishes status
only periodically and no event log), plus whatever the machine and its clients declare.
"""

from __future__ import annotations

import contextlib
import logging
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.context import Context
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from smacc_py.core import SmaccEngineParams, SmaccStateMachineBase
from smacc_py.ros.context import RosContext, attach_ros_context
from smacc_py.ros.introspection import IntrospectionPublisher
from smacc_py.ros.params import declare_dataclass_params

_log = logging.getLogger("smacc_py")

RUN_MODES = ("debug", "release")


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
        num_threads: executor threads.
    """

    def __init__(
        self,
        sm_type: type[SmaccStateMachineBase],
        *,
        context: Context | None = None,
        parameter_overrides: Sequence[Parameter] | None = None,
        num_threads: int = 4,
        sm_kwargs: dict[str, Any] | None = None,
    ) -> None:
        self.node = Node(
            sm_type.__name__, context=context, parameter_overrides=list(parameter_overrides or [])
        )
        self.params = declare_dataclass_params(self.node, RuntimeParams)
        engine = SmaccEngineParams(signal_detector_loop_freq=self.params.signal_detector_loop_freq)
        self.ros = RosContext(self.node, ReentrantCallbackGroup())
        self.sm = sm_type(params=engine, now=self.ros.now_s, **(sm_kwargs or {}))  # type: ignore[call-arg]
        attach_ros_context(self.sm, self.ros)
        self.sm.initialize()
        self.introspection = IntrospectionPublisher(
            self.node,
            self.sm,
            release_mode=self.params.run_mode == "release",
            callback_group=self.ros.callback_group,
        )
        self.sm.add_observer(self.introspection)
        self.executor = MultiThreadedExecutor(num_threads=num_threads, context=context)
        self.executor.add_node(self.node)
        self._tick = threading.Event()
        self._stopping = threading.Event()
        self._detector: threading.Thread | None = None
        self._spinner: threading.Thread | None = None
        self._timer: Any = None
        self.started_at_s: float | None = None  # node clock (s) when the machine was started

    # ------------------------------------------------------------------ lifecycle
    def start(self) -> None:
        """Start the SignalDetector thread, which enters the initial state (on the engine thread) as soon
        as the node clock is valid: under ``use_sim_time`` that is the first /clock message, so timers
        armed on entry do not fire at once when the clock jumps from 0 to the simulation's time."""
        self._detector = threading.Thread(
            target=self._detector_main, name=f"{self.sm.name}.signal_detector", daemon=True
        )
        self._detector.start()

    def _wait_for_clock(self) -> bool:
        waited = 0
        while self.ros.now_s() <= 0.0:
            if self._stopping.wait(0.01):
                return False
            waited += 1
            if waited == 200:
                self.node.get_logger().info("use_sim_time is true: waiting for /clock before starting")
        return True

    def _detector_main(self) -> None:
        if not self._wait_for_clock():
            return
        self.started_at_s = self.ros.now_s()
        self.sm.start(threaded=True)
        self._timer = self.node.create_timer(
            1.0 / self.params.signal_detector_loop_freq,
            self._tick.set,
            callback_group=MutuallyExclusiveCallbackGroup(),
        )
        while not self._stopping.is_set():
            if not self._tick.wait(0.2):
                continue
            self._tick.clear()
            if self._stopping.is_set():
                break
            try:
                self.sm.update()
            except Exception:
                _log.exception("%s: update() raised", self.sm.name)

    def spin(self) -> None:
        """Spin the executor in this thread until the context shuts down or ``shutdown()``.

        rclpy's ``spin()`` ends at the first exception a callback raises; in a background thread
        that silently freezes the machine (its clock stops with /clock, so even its timeouts never
        fire). Such an exception is logged with its traceback instead, and spinning goes on.
        """
        with contextlib.suppress(KeyboardInterrupt, ExternalShutdownException):
            while self.executor.context.ok() and not self._stopping.is_set():
                try:
                    self.executor.spin_once(timeout_sec=0.1)
                except (KeyboardInterrupt, ExternalShutdownException):
                    raise
                except Exception:
                    _log.exception("%s: a callback raised; the executor keeps spinning", self.sm.name)

    def spin_in_background(self) -> None:
        """Spin the executor in a daemon thread."""
        self._spinner = threading.Thread(target=self.spin, name=f"{self.sm.name}.executor", daemon=True)
        self._spinner.start()

    def shutdown(self) -> None:
        """Stop polling and the machine (behaviors' on_exit run: goals cancelled, twists zeroed),
        then the executor, then destroy the node. Safe to call more than once."""
        if self._stopping.is_set():
            return
        self._stopping.set()
        self._tick.set()
        if self._detector is not None:
            self._detector.join(5.0)
        if self.sm.is_running:
            self.sm.stop()
        self.sm.remove_observer(self.introspection)
        if self._timer is not None:
            self.node.destroy_timer(self._timer)
        self.introspection.destroy()
        self.executor.shutdown(timeout_sec=2.0)
        if self._spinner is not None:
            self._spinner.join(2.0)
        self.ros.destroy()
        self.node.destroy_node()
