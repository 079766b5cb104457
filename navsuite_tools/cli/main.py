"""``ros2py``: the ros2 CLI verbs for a pip-installed ROS 2 (``ros2py topic echo /odom`` ...).

Each verb group lives in its own module and registers its argparse subcommands; a verb is a
``handler(args, session) -> exit code`` (verbs that set ``offline`` get no ROS session).
A group given without a verb prints the group's help (its parser is in ``help_parser``).
User errors (unknown names or types, malformed YAML, timeouts) print one line on stderr and
exit with 1; Ctrl-C (SIGINT) or SIGTERM ends streaming verbs with 0.
"""

from __future__ import annotations

import argparse
import signal
import sys

from navsuite_tools.cli import action, interface, node, param, service, topic
from navsuite_tools.cli.common import CliError, request_interrupt, ros_session
from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument

_GROUPS = (topic, node, service, action, param, interface)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every verb group."""
    parser = argparse.ArgumentParser(
        prog="ros2py", description="ROS 2 command-line tools for a pip-installed ROS 2 (no ros2cli needed).",
    )
    add_executor_argument(parser)
    groups = parser.add_subparsers(dest="group", metavar="COMMAND")
    for group in _GROUPS:
        group.register(groups)
    return parser


def _interrupt_on_signals() -> None:
    """Make SIGINT and SIGTERM end a verb through KeyboardInterrupt, so it can clean up.

    The handler only notes the signal; the verb's next spin raises KeyboardInterrupt outside any
    callback (common.request_interrupt). A child started from a non-interactive shell in the
    background inherits an ignored SIGINT; installing a handler lets supervisors and tests stop
    streaming verbs (echo, hz, pub) with SIGINT.
    """
    signal.signal(signal.SIGINT, request_interrupt)
    signal.signal(signal.SIGTERM, request_interrupt)


def main(argv: list[str] | None = None) -> int:
    """Parse ``argv``, run the verb, and turn user errors into one line on stderr and exit code 1."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handler = getattr(args, "handler", None)
    if handler is None:
        getattr(args, "help_parser", parser).print_help(sys.stderr)
        return 1
    keep_dds_local()
    _interrupt_on_signals()
    try:
        if getattr(args, "offline", False):
            return int(handler(args, None))
        with ros_session(args.executor) as session:
            return int(handler(args, session))
    except CliError as exc:
        print(exc, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 0
    except BrokenPipeError:  # e.g. `ros2py topic echo /scan | head`
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    sys.exit(main())
