"""A process built on ros_tools.runtime.runner.run_nodes, for the runner's tests (run as a child).

    python -m tests.helpers.runner_probe finish CODE   # finished() returns CODE at its first check
    python -m tests.helpers.runner_probe serve         # spins until a signal; the hook says it ran

Each fact the tests check is one line on stdout, written as it happens (flushed): ``ready`` with the
signal setup seen from inside the run, ``hook`` from before_shutdown with whether the context was
still up, ``after`` with the handlers once run_nodes returned. The exit code is run_nodes'.
"""

from __future__ import annotations

import signal
import sys
from collections.abc import Sequence
from typing import Any

from ros_tools.runtime.runner import run_nodes

INTERRUPTED = 43  # the serve mode's exit code after SIGINT or SIGTERM


def _handler_name(sig: signal.Signals) -> str:
    """Who handles ``sig``: the qualified name of a Python handler, else SIG_DFL / SIG_IGN / None."""
    handler = signal.getsignal(sig)
    if isinstance(handler, signal.Handlers):
        return handler.name
    return getattr(handler, "__qualname__", str(handler))


def main(argv: Sequence[str]) -> int:
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions, get_current_signal_handlers_options

    mode = argv[0]

    def on_start(executor: Any, nodes: Sequence[Any]) -> None:
        rclpy_handlers = get_current_signal_handlers_options() != SignalHandlerOptions.NO
        print(f"ready sigterm={_handler_name(signal.SIGTERM)} sigint={_handler_name(signal.SIGINT)} "
              f"rclpy_handlers={rclpy_handlers}", flush=True)

    def hook(executor: Any, nodes: Sequence[Any]) -> None:
        print(f"hook context_ok={nodes[0].context.ok()}", flush=True)

    def finished(nodes: Sequence[Any]) -> int | None:
        return int(argv[1]) if mode == "finish" else None

    code = run_nodes(lambda: [Node("runner_probe")], role="runner_probe", rclpy_args=["runner_probe"],
                     on_start=on_start, finished=finished, before_shutdown=hook,
                     interrupted_code=INTERRUPTED)
    print(f"after sigterm={_handler_name(signal.SIGTERM)} sigint={_handler_name(signal.SIGINT)}", flush=True)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
