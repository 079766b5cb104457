"""What every verb shares: the CLI node, bounded waits, name handling and QoS options.

Every wait has a deadline and, when it expires, a :class:`CliError` that says what was awaited.
``main`` prints a CliError as one line on stderr and exits with code 1, so user mistakes
(unknown topic, bad type, malformed YAML) never show a traceback.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden

from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import make_executor
from ros_tools.runtime.runner import ros_process

#: Minimum seconds list/info verbs listen to DDS discovery before answering (ros2cli's default).
DEFAULT_SPIN_TIME = 0.5
#: Seconds without any change in the discovered graph after which a list is taken as complete.
#: Fast DDS on localhost finds a peer 0.4 to 2.5 s after start, so a fixed short spin misses nodes.
SETTLE_TIME = 1.0
#: Seconds a verb waits for a named topic, node, service or action to appear, or for a reply.
DEFAULT_TIMEOUT = 5.0


class CliError(Exception):
    """A user-facing failure; ``main`` prints it as one line on stderr and exits with code 1."""


_interrupted = [False]


def request_interrupt(_signum: int = 0, _frame: object = None) -> None:
    """A SIGINT/SIGTERM handler: note the request; the next :meth:`Session.spin_once` raises it.

    Why not raise KeyboardInterrupt at once: the signal is handled wherever the main thread runs
    Python, which is usually inside a subscription callback called by the executor; the
    EventsExecutor then logs the interrupt as a FATAL callback exception before passing it on.
    """
    _interrupted[0] = True


@dataclass
class Session:
    """The hidden CLI node and the executor that spins it (one per command invocation).

    Verbs spin it from the main thread with bounded ``spin_once`` calls (never from a callback);
    callbacks only store what arrives.
    """

    node: Node
    executor: Executor

    def spin_once(self, timeout: float) -> None:
        """Run at most one callback, waiting up to ``timeout`` s for it.

        Raises:
            KeyboardInterrupt: Ctrl-C or SIGTERM arrived (see :func:`request_interrupt`).
        """
        self.executor.spin_once(timeout_sec=timeout)
        if _interrupted[0]:
            _interrupted[0] = False
            raise KeyboardInterrupt

    def spin_for(self, seconds: float) -> None:
        """Process callbacks and discovery for ``seconds`` (wall clock)."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            self.spin_once(min(left, 0.05))

    def discover_graph(self, spin_time: float, timeout: float) -> None:
        """Listen to discovery until the graph looks complete (list verbs have no name to wait for).

        Spins at least ``spin_time`` seconds; then until some other node has been seen and the
        graph (nodes, topics, services) has not changed for ``SETTLE_TIME`` seconds, or until
        ``timeout`` seconds in all (an empty graph answers after the timeout).
        """
        own = self.node.get_name()
        start = time.monotonic()
        snapshot: object = None
        changed = start
        while True:
            now = time.monotonic()
            current = (
                sorted(self.node.get_node_names_and_namespaces()),
                sorted(self.node.get_topic_names_and_types()),
                sorted(self.node.get_service_names_and_types()),
            )
            if current != snapshot:
                snapshot, changed = current, now
            others = any(name != own for name, _ in current[0])
            settled = others and now - changed >= SETTLE_TIME
            if now - start >= spin_time and (settled or now - start >= timeout):
                return
            self.spin_once(0.05)

    def wait(self, predicate: Callable[[], bool], seconds: float) -> bool:
        """Spin until ``predicate()`` holds (True) or ``seconds`` pass (False); a
        ros_tools.runtime.actions ``Wait``."""
        deadline = time.monotonic() + seconds
        while not predicate():
            if time.monotonic() > deadline:
                return False
            self.spin_once(0.05)
        return True

    def spin_until(self, predicate: Callable[[], bool], timeout: float, what: str) -> None:
        """Spin until ``predicate()`` holds.

        Raises:
            CliError: after ``timeout`` seconds, naming ``what`` was awaited.
        """
        if not self.wait(predicate, timeout):
            raise CliError(f"timed out after {timeout:.1f} s waiting for {what}")

    def wait_future(self, future: Any, timeout: float, what: str) -> Any:
        """Spin until ``future`` completes and return its result (bounded by ``timeout``)."""
        self.spin_until(future.done, timeout, what)
        exception = future.exception()
        if exception is not None:
            raise CliError(f"{what} failed: {exception}")
        return future.result()


@contextmanager
def ros_session(executor_kind: str | None = None) -> Iterator[Session]:
    """Initialise rclpy, create the hidden ``_ros2py_<pid>`` node, and tear both down afterwards.

    rclpy's own SIGINT handler is disabled so Ctrl-C raises KeyboardInterrupt in the verb, which
    can then clean up (for example cancel a running action goal) while the context still works.
    ``executor_kind``: ``events`` or ``single`` (None: ``$NAVSUITE_EXECUTOR`` or ``events``).
    """
    keep_dds_local()
    with ros_process(context=Context(), handle_signals=False) as process:  # the verb's KeyboardInterrupt
        node = None
        executor = None
        try:
            node = rclpy.create_node(
                f"_ros2py_{os.getpid()}", context=process.context, start_parameter_services=False,
                enable_rosout=False,
            )
            executor = make_executor(executor_kind, process.context)
            executor.add_node(node)
            yield Session(node, executor)
        finally:
            if executor is not None:
                executor.shutdown(timeout_sec=1.0)
            if node is not None:
                node.destroy_node()  # type: ignore[no-untyped-call]


def add_command(subparsers: Any, command: str, help_text: str) -> Any:
    """``ros2py <command>``'s parser; its verbs' subparsers (``verb`` names the chosen one)."""
    parser = subparsers.add_parser(command, help=help_text)
    parser.set_defaults(help_parser=parser)
    return parser.add_subparsers(dest="verb", metavar="VERB")


def add_list_verb(verbs: Any, plural: str, handler: Callable[..., int], hidden: bool = True) -> None:
    """``<command> list`` with ros2cli's options: ``-t/--show-types``, ``-c/--count-<plural>`` and, where
    names can be hidden (topics, services), ``--include-hidden-<plural>``."""
    p = verbs.add_parser("list", help=f"list the {plural} in the graph")
    p.add_argument("-t", "--show-types", action="store_true", help=f"also print each {plural[:-1]}'s type")
    p.add_argument("-c", f"--count-{plural}", action="store_true", help=f"only print the number of {plural}")
    if hidden:
        p.add_argument(f"--include-hidden-{plural}", action="store_true", help=f"include hidden {plural}")
    add_wait_options(p)
    p.set_defaults(handler=handler)


def add_wait_options(parser: argparse.ArgumentParser) -> None:
    """The discovery options every ROS-facing verb accepts."""
    parser.add_argument(
        "--spin-time", type=float, default=DEFAULT_SPIN_TIME, metavar="SECONDS",
        help=f"least time list/info verbs listen to discovery (default {DEFAULT_SPIN_TIME}); lists "
        f"then wait until the graph has been unchanged for {SETTLE_TIME} s",
    )
    parser.add_argument(
        "--timeout", type=float, default=DEFAULT_TIMEOUT, metavar="SECONDS",
        help=f"how long to wait for a named entity to appear or reply (default {DEFAULT_TIMEOUT})",
    )


def full_name(name: str) -> str:
    """A topic, service, action or node name made absolute (the CLI node lives in ``/``)."""
    name = name.strip()
    if not name:
        raise CliError("empty name")
    return name if name.startswith("/") else f"/{name}"


def visible(
    names_and_types: list[tuple[str, list[str]]], include_hidden: bool,
) -> list[tuple[str, list[str]]]:
    """Sorted (name, types) pairs without hidden names (a path token starting with ``_``)."""
    return sorted(
        (name, types) for name, types in names_and_types
        if include_hidden or not topic_or_service_is_hidden(name)
    )


def print_names(pairs: list[tuple[str, list[str]]], show_types: bool, count_only: bool) -> None:
    """Print ``name`` or ``name [type; type]`` per line, or only their count."""
    if count_only:
        print(len(pairs))
        return
    for name, types in pairs:
        print(f"{name} [{'; '.join(types)}]" if show_types else name)


def wait_for_type(
    session: Session, lookup: Callable[[], list[tuple[str, list[str]]]], name: str, what: str, timeout: float,
) -> str:
    """The type of a topic, service or action ``name`` once it appears in the graph.

    Raises:
        CliError: ``Unknown <what> '<name>'`` after ``timeout`` seconds, or several types.
    """
    found: list[str] = []

    def appeared() -> bool:
        found[:] = next((types for n, types in lookup() if n == name), [])
        return bool(found)

    try:
        session.spin_until(appeared, timeout, f"{what} '{name}'")
    except CliError:
        raise CliError(f"Unknown {what} '{name}' (waited {timeout:.1f} s for it to appear)") from None
    if len(found) > 1:
        raise CliError(f"{what} '{name}' has several types ({'; '.join(found)}): pass the type explicitly")
    return found[0]


def node_names(session: Session, include_hidden: bool = False) -> list[str]:
    """Fully qualified names of the nodes in the graph, sorted."""
    names = []
    for name, namespace in session.node.get_node_names_and_namespaces():
        if name.startswith("_") and not include_hidden:
            continue
        names.append(f"{namespace.rstrip('/')}/{name}")
    return sorted(names)


def wait_for_node(session: Session, name: str, timeout: float) -> tuple[str, str]:
    """Wait until node ``name`` is in the graph; returns its (name, namespace).

    Raises:
        CliError: ``Node not found`` after ``timeout`` seconds.
    """
    target = full_name(name)

    def present() -> bool:
        return target in node_names(session, include_hidden=True)

    try:
        session.spin_until(present, timeout, f"node '{target}'")
    except CliError:
        raise CliError(f"Node not found: '{target}' (waited {timeout:.1f} s for it to appear)") from None
    namespace, _, short = target.rpartition("/")
    return short, namespace or "/"


# ---------------------------------------------------------------- QoS options (ros2 topic names)
_RELIABILITY = {"reliable": ReliabilityPolicy.RELIABLE, "best_effort": ReliabilityPolicy.BEST_EFFORT}
_DURABILITY = {"volatile": DurabilityPolicy.VOLATILE, "transient_local": DurabilityPolicy.TRANSIENT_LOCAL}
_HISTORY = {"keep_last": HistoryPolicy.KEEP_LAST, "keep_all": HistoryPolicy.KEEP_ALL}


def add_qos_options(parser: argparse.ArgumentParser, default_depth: int) -> None:
    """The ``--qos-*`` options of ``ros2 topic echo|pub|hz``."""
    parser.add_argument("--qos-reliability", choices=sorted(_RELIABILITY),
                        help="reliability (default: match the publishers)")
    parser.add_argument("--qos-durability", choices=sorted(_DURABILITY),
                        help="durability (default: match the publishers)")
    parser.add_argument("--qos-history", choices=sorted(_HISTORY), default="keep_last")
    parser.add_argument("--qos-depth", type=int, default=default_depth,
                        help=f"queue depth (default {default_depth})")


def qos_from_args(args: argparse.Namespace, session: Session | None = None, topic: str = "") -> QoSProfile:
    """A QoS profile from the options; unset policies follow the topic's current publishers.

    As in ``ros2 topic echo``: reliable only if every publisher is reliable, transient local only
    if every publisher is transient local; without publishers, reliable and volatile.
    """
    publishers = session.node.get_publishers_info_by_topic(topic) if session and topic else []
    profile = QoSProfile(  # type: ignore[no-untyped-call]
        depth=max(1, args.qos_depth), history=_HISTORY[args.qos_history],
    )
    if args.qos_reliability is not None:
        profile.reliability = _RELIABILITY[args.qos_reliability]
    elif publishers and any(p.qos_profile.reliability != ReliabilityPolicy.RELIABLE for p in publishers):
        profile.reliability = ReliabilityPolicy.BEST_EFFORT
    else:
        profile.reliability = ReliabilityPolicy.RELIABLE
    if args.qos_durability is not None:
        profile.durability = _DURABILITY[args.qos_durability]
    elif publishers and all(p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in publishers):
        profile.durability = DurabilityPolicy.TRANSIENT_LOCAL
    else:
        profile.durability = DurabilityPolicy.VOLATILE
    return profile


def now_msg(session: Session) -> Any:
    """The CLI node's current time as ``builtin_interfaces/msg/Time`` (for ``now``/``auto`` values)."""
    return session.node.get_clock().now().to_msg()
