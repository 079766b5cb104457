"""The one shape of every node process: init, build, share the clock, take part in lockstep, spin,
stop on Ctrl-C or SIGTERM, and tear everything down.

Why one runner: each server's ``main()`` used to repeat the same init/spin/teardown block, each
with its own executor choice, and nodes were left to the garbage collector at exit (which printed
"exception was never retrieved: cannot use Destroyable" as pending goals met destroyed entities).
Here teardown is explicit and ordered: leave lockstep, stop the executor (pending coroutines are
cancelled with it), destroy every waitable (action servers and clients) and then the nodes.

A callback that raises is logged with its traceback and the process keeps serving: a fault in one
goal must become a result, never a dead stack. The module imports rclpy only inside its functions, so
a command can install :class:`StopOnSignal` before its slow imports.

Two entry points, one underneath the other:

- :func:`run_nodes` is a whole process in one call: nodes built by a function, spun until Ctrl-C,
  SIGTERM or a ``finished`` check that returns the exit code, with a ``before_shutdown`` hook that
  still has a live context (cancel goals, publish a last stop).
- :func:`ros_process` is the part every process shares, as a context manager, for the few whose main
  loop is not "spin until done" (a viewer with its own threads, a state machine runtime that owns its
  executor, a library function called inside someone else's process): ``rclpy.init`` with the
  process's own arguments and rclpy's signal handler off, SIGINT and SIGTERM only raising a flag
  (:class:`StopOnSignal`), and the context shut down on the way out.

Why rclpy's own signal handler stays off everywhere: it shuts the context down the moment SIGTERM
arrives, before the process can cancel its goals or leave lockstep, and a process once spun on for an
hour after SIGTERM that way (nav_stack/ros/autonomy/node.py).
"""

from __future__ import annotations

import logging
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument, make_executor

if TYPE_CHECKING:
    from ros_tools.runtime.lockstep import LockstepParticipant

_log = logging.getLogger("ros_tools.runtime")

BuildNodes = Callable[[], Sequence[Any]]
#: The exit code of a process that has finished by itself, None while it runs; called with the nodes.
Finished = Callable[[Sequence[Any]], "int | None"]
#: Called with (executor, nodes): readiness timers and banners before spinning, goal cancels after.
NodesHook = Callable[[Any, Sequence[Any]], None]
SPIN_SLICE = 0.1  # s: the longest the process goes without checking for Ctrl-C


def split_runner_flags(argv: Sequence[str],
                       description: str | None = None) -> tuple[bool, str | None, list[str]]:
    """(``--autostart`` given, ``--executor`` value, the remaining arguments) of a command line.

    Only arguments before ``--ros-args`` are looked at; the rest is rclpy's. ``-h``/``--help`` there
    prints the usage (with ``description``, e.g. the server module's docstring) and exits 0: a node
    started by ``--help`` would otherwise spin, waiting for a lifecycle manager that never comes.
    """
    import argparse
    import os

    args = list(argv)
    split = args.index("--ros-args") if "--ros-args" in args else len(args)
    parser = argparse.ArgumentParser(
        prog=os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else None, description=description,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="ROS arguments follow --ros-args, e.g. --ros-args --params-file config/nav2_params.yaml "
               "-p use_sim_time:=true")
    parser.add_argument("--autostart", action="store_true",
                        help="configure and activate the nodes (otherwise a lifecycle manager does)")
    add_executor_argument(parser)
    known, rest = parser.parse_known_args(args[:split])
    return known.autostart, known.executor, rest + args[split:]


def destroy_nodes(nodes: Sequence[Any]) -> None:
    """Destroy every waitable (action servers and clients) of each node, then the node, newest first."""
    for node in reversed(list(nodes)):
        for waitable in list(getattr(node, "waitables", [])):
            destroy = getattr(waitable, "destroy", None)
            if destroy is not None:
                try:
                    destroy()
                except Exception:  # already destroyed by its owner: nothing left to release
                    _log.debug("waitable of %s was already destroyed", node.get_name())
        try:
            node.destroy_node()
        except Exception:  # a node whose own teardown met an entity destroyed above
            _log.debug("%s: destroy_node raised after its waitables were destroyed", node.get_name(),
                       exc_info=True)


def spin_until_shutdown(executor: Any, name: str = "process",
                        stopped: Callable[[], bool] | None = None,
                        stop: StopOnSignal | None = None) -> None:
    """Spin until the context shuts down (Ctrl-C, SIGTERM, ``rclpy.shutdown``) or ``stopped()``,
    logging callback faults.

    A thread spinning in the background must be stopped (``stopped``) and joined before
    ``executor.shutdown()``: the EventsExecutor's shutdown waits for a gap between two spins, and a
    loop that spins again at once may never leave it one.

    In the main thread, Ctrl-C and SIGTERM only raise a flag that the loop checks between callbacks:
    a KeyboardInterrupt raised inside a callback would be logged by the EventsExecutor as a FATAL
    "Exception in callback" in the middle of an orderly shutdown. ``stop`` is the flag of a process
    that installed it already (:func:`ros_process`); without it the loop installs its own for as long
    as it spins.
    """
    from rclpy.executors import ExternalShutdownException

    from ros_tools.runtime.executor_watch import ExecutorWatch

    own_stop = stop is None
    flag = StopOnSignal() if stop is None else stop
    watch = ExecutorWatch(executor, name)
    watch.spinning_thread = threading.get_ident()
    watch.start()
    try:
        while executor.context.ok() and not flag.requested and not (stopped is not None and stopped()):
            try:
                # spin_once in a loop, not spin(): the EventsExecutor's spin() never returns to
                # Python; spin_once hands back control at least every SPIN_SLICE s.
                executor.spin_once(timeout_sec=SPIN_SLICE)
            except (KeyboardInterrupt, ExternalShutdownException):
                return
            except Exception:
                if not executor.context.ok():
                    return
                _log.exception("%s: a callback raised; the executor keeps spinning", name)
    finally:
        watch.stop()
        if own_stop:
            flag.restore()


class StopOnSignal:
    """While alive (main thread only), SIGINT and SIGTERM set ``requested`` instead of raising.

    Why: Python raises KeyboardInterrupt wherever the main thread is, and while it spins that is
    often a callback; the executor then logs an ordinary Ctrl-C as a fatal callback exception with
    its traceback. A loop that checks ``requested`` between spins stops cleanly instead. The handlers
    are set explicitly, also for a process a shell started in the background (which inherits SIGINT
    ignored). Off the main thread (a test calling a run function from a thread) nothing is installed.

    Args:
        on_stop: also called from the handler, for a loop that is not the runner's and has its own
            stop request (e.g. ``SmaccRuntime.request_stop``); it must only set a flag.
    """

    def __init__(self, on_stop: Callable[[], None] | None = None) -> None:
        import signal
        import threading

        self.requested = False
        self.on_stop = on_stop
        self._previous: dict[int, Any] = {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._on_signal)

    def _on_signal(self, signum: int, frame: object) -> None:
        self.requested = True
        if self.on_stop is not None:
            self.on_stop()

    def restore(self) -> None:
        """Put the previous handlers back."""
        import signal

        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous = {}


class RosProcess:
    """What :func:`ros_process` yields: the initialised context and the process's stop flag."""

    def __init__(self, context: Any, stop: StopOnSignal | None) -> None:
        self.context = context
        self.stop = stop

    @property
    def stop_requested(self) -> bool:
        """Whether SIGINT or SIGTERM arrived (never, when the caller handles signals itself)."""
        return self.stop is not None and self.stop.requested

    def ok(self) -> bool:
        """The context is up and no stop was asked for: the condition of a main loop."""
        return bool(self.context.ok()) and not self.stop_requested

    def executor(self, kind: str | None = None) -> Any:
        """A new executor on this context (``events`` or ``single``; None: ``$NAVSUITE_EXECUTOR``)."""
        return make_executor(kind, self.context)


@contextmanager
def ros_process(rclpy_args: Sequence[str] | None = None, *, context: Any = None,
                handle_signals: bool = True) -> Iterator[RosProcess]:
    """rclpy initialised for the block, without rclpy's signal handler; the context shut down after.

    Args:
        rclpy_args: the arguments rclpy sees (program name, then ``--ros-args`` ...); None takes
            ``sys.argv``, as ``rclpy.init`` does.
        context: an uninitialised ``rclpy.context.Context`` to initialise (a library function that runs
            beside other contexts); None initialises rclpy's default context.
        handle_signals: install :class:`StopOnSignal` for the block (its flag is ``stop_requested``).
            False for a library function inside a process whose signals belong to its caller.

    The flag is installed before ``rclpy.init`` and stays until the context is down, so a Ctrl-C
    during start-up or teardown never surfaces as a KeyboardInterrupt in the middle of either. The
    suite's DDS defaults (ros_tools.dds.keep_dds_local) are applied first: every process the project
    starts keeps discovery on this machine unless the user chose a range, and no import does it.
    """
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    from rclpy.utilities import get_default_context

    keep_dds_local()  # before the first participant: Fast DDS reads the settings once
    stop = StopOnSignal() if handle_signals else None
    try:
        rclpy.init(args=None if rclpy_args is None else list(rclpy_args), context=context,
                   signal_handler_options=SignalHandlerOptions.NO)
        try:
            yield RosProcess(get_default_context() if context is None else context, stop)
        finally:
            rclpy.try_shutdown(context=context)
    finally:
        if stop is not None:
            stop.restore()


def activate(nodes: Sequence[Any]) -> None:
    """Configure and activate the lifecycle nodes among ``nodes`` in order (what ``--autostart`` does
    without a lifecycle manager; owned nodes such as costmaps follow their owner's transitions)."""
    from rclpy.lifecycle import LifecycleNode

    owned = {id(getattr(node, "costmap_node", None)) for node in nodes}
    for node in nodes:
        if isinstance(node, LifecycleNode) and id(node) not in owned:
            node.trigger_configure()
            node.trigger_activate()


def run_nodes(build_nodes: BuildNodes, *, role: str, rclpy_args: Sequence[str] | None = None,
              executor: str | None = None, autostart: bool = False,
              ready: Callable[[], bool] | None = None, on_start: NodesHook | None = None,
              finished: Finished | None = None, before_shutdown: NodesHook | None = None,
              interrupted_code: int | Callable[[Sequence[Any]], int] = 0, lockstep: bool = True) -> int:
    """Run one process of nodes until it finishes, Ctrl-C or SIGTERM; its exit code.

    Args:
        build_nodes: builds the nodes (after ``rclpy.init``, on rclpy's default context). What it
            raises (e.g. a configuration error) leaves ``run_nodes`` after the teardown.
        role: the process's name in lockstep warnings and logs (``nav2``, ``localization``...).
        rclpy_args: the arguments rclpy sees (``--ros-args`` ...); None takes ``sys.argv``.
        executor: ``events`` or ``single``; None takes ``$NAVSUITE_EXECUTOR`` or ``events``.
        autostart: configure and activate the lifecycle nodes (normally a lifecycle manager does).
        ready: lockstep holds the simulator until it returns True (e.g. managers active).
        on_start: called with (executor, nodes) just before spinning (readiness timers, banners).
        finished: for a process that ends by itself: checked between callbacks (at least every
            SPIN_SLICE s), its first int ends the run and is the exit code.
        before_shutdown: called with (executor, nodes) once spinning has ended, however it ended,
            while the context is still up and the process still in lockstep: the place to cancel
            goals or publish a last stop. It may spin ``executor`` itself, bounded by its own wait.
        interrupted_code: the exit code after Ctrl-C, SIGTERM or an external shutdown; a function of
            the nodes when the outcome so far decides it.
        lockstep: take part in lockstep when the first node uses sim time (False for the process
            that is the clock, or one that only watches).
    """
    from ros_tools.runtime.lockstep import LockstepParticipant, uses_sim_time
    from ros_tools.shared_clock import share_sim_time

    args = list(sys.argv if rclpy_args is None else rclpy_args)
    code: int | None = None

    def done(nodes: Sequence[Any]) -> bool:
        nonlocal code
        if finished is not None and code is None:
            code = finished(nodes)
        return code is not None

    def interrupted(nodes: Sequence[Any]) -> int:
        return interrupted_code(nodes) if callable(interrupted_code) else interrupted_code

    # The runner handles Ctrl-C and SIGTERM itself (a flag checked between callbacks), so the context
    # is still alive during teardown: nodes leave lockstep and cancel their goals on the way out.
    with ros_process(args) as process:
        nodes: list[Any] = []
        participant: LockstepParticipant | None = None
        spinner: Any = None
        try:
            nodes = list(build_nodes())
            share_sim_time(nodes)
            spinner = process.executor(executor)
            for node in nodes:
                spinner.add_node(node)
            if lockstep and nodes and uses_sim_time(nodes[0]):
                participant = LockstepParticipant(nodes[0], role, ready)
            if autostart:
                activate(nodes)
            if on_start is not None:
                on_start(spinner, nodes)
            if not done(nodes):
                spin_until_shutdown(spinner, role, lambda: done(nodes), process.stop)
            if code is None:
                code = interrupted(nodes)
            if before_shutdown is not None and process.context.ok():
                before_shutdown(spinner, nodes)
        except KeyboardInterrupt:  # a signal before the flag was installed, or off the main thread
            code = interrupted(nodes) if code is None else code
        finally:
            if participant is not None and process.context.ok():  # else nobody can hear it leave
                participant.destroy()
            if spinner is not None:
                spinner.shutdown()
            destroy_nodes(nodes)
    return code if code is not None else interrupted(nodes)
