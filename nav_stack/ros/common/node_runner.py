"""The ``main()`` of every nav_stack server, ``python -m nav_stack.ros.<group>.<server> [--autostart]
[--executor events|single] [--ros-args ...]``.

One shape for all of them (ros_tools.runtime.runner): the nodes (a server and the costmap node it
owns) spin on one EventsExecutor (``--executor single`` falls back to rclpy's
SingleThreadedExecutor). Nothing in a server blocks a callback: action goals are coroutines that
await their outcome while node-clock timers step them, so one thread serves every goal.
``--autostart`` configures and activates the nodes (normally a lifecycle manager does it).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import Any

from rclpy.parameter import Parameter

from ros_tools.runtime.runner import run_nodes, split_runner_flags


def run(build_nodes: Callable[[], Sequence[object]], argv: Sequence[str] | None = None,
        role: str | None = None) -> int:
    """Build the nodes, optionally bring them up, spin until Ctrl-C or SIGTERM; the exit code.

    ``role`` names the process in lockstep warnings (default: the program name).
    """

    args = list(sys.argv if argv is None else argv)
    module = sys.modules.get(getattr(build_nodes, "__module__", ""), None)
    autostart, executor, rclpy_args = split_runner_flags(args, getattr(module, "__doc__", None))
    name = role or (args[0].rsplit("/", 1)[-1] if args else "nav_stack")
    return run_nodes(build_nodes, role=name, rclpy_args=rclpy_args, executor=executor, autostart=autostart)


def with_sim_time(kwargs: dict[str, Any], use_sim_time: bool) -> dict[str, Any]:
    """A server's node constructor ``kwargs`` with ``use_sim_time`` added to its parameter overrides
    when asked: what every server's ``build_nodes(use_sim_time=...)`` passes on."""
    if use_sim_time:
        kwargs["parameter_overrides"] = [*kwargs.get("parameter_overrides", []),
                                         Parameter("use_sim_time", value=True)]
    return kwargs
