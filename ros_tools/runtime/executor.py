"""Which rclpy executor spins a process, chosen in one place.

Why the EventsExecutor: rclpy's Python executors rebuild their wait set in Python on every wake-up.
On this machine (../shared/reference/executor_bench.py, four 100 Hz LaserScan publishers and 16
subscriptions in one process) the MultiThreadedExecutor delivered 1,832 of 16,000 messages at 5.5 ms
of CPU each, the SingleThreadedExecutor all of them at 375 µs each, and the C++ EventsExecutor
(``rclpy.experimental``, in the Jazzy rclpy wheel) all of them at 91 µs each. Every callback in the
suite is short and never blocks, so one thread is enough and no callback group is needed.

The fallback exists because the EventsExecutor is still "experimental" upstream: it supports no
guard conditions (nothing here uses them). Choose with ``--executor single`` on a command that
offers it, or ``NAVSUITE_EXECUTOR=single`` for every process a launch starts.
"""

from __future__ import annotations

import os
from typing import Any

EXECUTOR_ENV = "NAVSUITE_EXECUTOR"
EXECUTOR_KINDS = ("events", "single")
DEFAULT_EXECUTOR = "events"


def executor_kind(requested: str | None = None) -> str:
    """The executor kind to use: ``requested``, else ``$NAVSUITE_EXECUTOR``, else ``events``.

    Raises:
        ValueError: the kind is not one of EXECUTOR_KINDS (naming where it came from).
    """
    source, kind = ("--executor", requested) if requested else (EXECUTOR_ENV, os.environ.get(EXECUTOR_ENV))
    kind = (kind or DEFAULT_EXECUTOR).strip().lower()
    if kind not in EXECUTOR_KINDS:
        raise ValueError(f"{source}: executor must be one of {', '.join(EXECUTOR_KINDS)}, got {kind!r}")
    return kind


def make_executor(kind: str | None = None, context: Any = None) -> Any:
    """A new executor of ``executor_kind(kind)`` on ``context`` (the default context when None)."""
    if executor_kind(kind) == "events":
        from rclpy.experimental import EventsExecutor

        return EventsExecutor(context=context)
    from rclpy.executors import SingleThreadedExecutor

    return SingleThreadedExecutor(context=context)


def add_executor_argument(parser: Any) -> None:
    """Add ``--executor {events,single}`` to an argparse parser (default: $NAVSUITE_EXECUTOR or events)."""
    parser.add_argument("--executor", choices=EXECUTOR_KINDS, default=None,
                        help=f"rclpy executor (default: ${EXECUTOR_ENV} or {DEFAULT_EXECUTOR})")


def reentrant_default_group(node: Any) -> None:
    """Make ``node``'s default callback group reentrant; call it first thing in a node's ``__init__``.

    Why: one thread runs every callback of a process, so callback groups no longer keep callbacks
    apart. They still matter on the Python fallback executor (``--executor single``): there a
    coroutine callback (an async execute or service callback) holds its group until it returns,
    and a timer or response it awaits in the same mutually exclusive group would never run. rclpy
    has no constructor argument for the default group, hence the attribute.
    """
    from rclpy.callback_groups import ReentrantCallbackGroup

    node._default_callback_group = ReentrantCallbackGroup()
