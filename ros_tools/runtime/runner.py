"""The one shape of every node process: init, build, share the clock, take part in lockstep, spin,
stop on Ctrl-C or SIGTERM, and tear everything down.

Why one runner: each server's ``main()`` used to repeat the same init/spin/teardown block, each
with its own executor choice, and nodes were left to the garbage collector at exit (which printed
"exception was never retrieved: cannot use Destroyable" as pending goals met destroyed entities).
Here teardown is explicit and ordered: leave lockstep, stop the executor (pending coroutines are
cancelled with it), destroy every waitable (action servers and clients) and then the nodes.

A callback that raises is logged with its traceback and the process keeps serving: a fault in one
goal must become a result, never a dead stack.
"""

from __future__ import annotations

import logging
import sys
import threading
from collections.abc import Callable, Sequence
from typing import Any

from ros_tools.runtime.executor import add_executor_argument, make_executor
from ros_tools.runtime.executor_watch import ExecutorWatch
from ros_tools.runtime.lockstep import LockstepParticipant, uses_sim_time

_log = logging.getLogger("ros_tools.runtime")

BuildNodes = Callable[[], Sequence[Any]]
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
                        stopped: Callable[[], bool] | None = None) -> None:
    """Spin until the context shuts down (Ctrl-C, SIGTERM, ``rclpy.shutdown``) or ``stopped()``,
    logging callback faults.

    A thread spinning in the background must be stopped (``stopped``) and joined before
    ``executor.shutdown()``: the EventsExecutor's shutdown waits for a gap between two spins, and a
    loop that spins again at once may never leave it one.

    In the main thread, Ctrl-C and SIGTERM only raise a flag that the loop checks between callbacks:
    a KeyboardInterrupt raised inside a callback would be logged by the EventsExecutor as a FATAL
    "Exception in callback" in the middle of an orderly shutdown.
    """
    from rclpy.executors import ExternalShutdownException

    stop = StopOnSignal()
    watch = ExecutorWatch(executor, name)
    watch.spinning_thread = threading.get_ident()
    watch.start()
    try:
        while executor.context.ok() and not stop.requested and not (stopped is not None and stopped()):
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
        stop.restore()


class StopOnSignal:
    """While alive (main thread only), SIGINT and SIGTERM set ``requested`` instead of raising.

    Why: Python raises KeyboardInterrupt wherever the main thread is, and while it spins that is
    often a callback; the executor then logs an ordinary Ctrl-C as a fatal callback exception with
    its traceback. A loop that checks ``requested`` between spins stops cleanly instead. Off the main
    thread (a test calling a run function from a thread) nothing is installed.
    """

    def __init__(self) -> None:
        import signal
        import threading

        self.requested = False
        self._previous: dict[int, Any] = {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._on_signal)

    def _on_signal(self, signum: int, frame: object) -> None:
        self.requested = True

    def restore(self) -> None:
        """Put the previous handlers back."""
        import signal

        for sig, handler in self._previous.items():
            signal.signal(sig, handler)


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
              ready: Callable[[], bool] | None = None,
              on_start: Callable[[Any, Sequence[Any]], None] | None = None) -> int:
    """Run one process of nodes until Ctrl-C or SIGTERM; its exit code.

    Args:
        build_nodes: builds the nodes (after ``rclpy.init``).
        role: the process's name in lockstep warnings and logs (``nav2``, ``localization``...).
        rclpy_args: the arguments rclpy sees (``--ros-args`` ...); None takes ``sys.argv``.
        executor: ``events`` or ``single``; None takes ``$NAVSUITE_EXECUTOR`` or ``events``.
        autostart: configure and activate the lifecycle nodes (normally a lifecycle manager does).
        ready: lockstep holds the simulator until it returns True (e.g. managers active).
        on_start: called with (executor, nodes) just before spinning (readiness timers, banners).
    """
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    from ros_tools.shared_clock import share_sim_time

    # The runner handles Ctrl-C and SIGTERM itself (spin_until_shutdown), so the context is still
    # alive during teardown: nodes leave lockstep and cancel their goals on the way out.
    rclpy.init(args=list(sys.argv if rclpy_args is None else rclpy_args),
               signal_handler_options=SignalHandlerOptions.NO)
    nodes: list[Any] = []
    participant: LockstepParticipant | None = None
    spinner: Any = None
    try:
        nodes = list(build_nodes())
        share_sim_time(nodes)
        spinner = make_executor(executor)
        for node in nodes:
            spinner.add_node(node)
        if nodes and uses_sim_time(nodes[0]):
            participant = LockstepParticipant(nodes[0], role, ready)
        if autostart:
            activate(nodes)
        if on_start is not None:
            on_start(spinner, nodes)
        spin_until_shutdown(spinner, role)
    except KeyboardInterrupt:
        pass
    finally:
        if participant is not None:
            participant.destroy()
        if spinner is not None:
            spinner.shutdown()
        destroy_nodes(nodes)
        rclpy.try_shutdown()
    return 0
