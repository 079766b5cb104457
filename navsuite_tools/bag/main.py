"""``navsuite-bag``: record, inspect, replay and report on MCAP recordings.

    navsuite-bag record -a -o run.mcap --use-sim-time --max-duration 60
    navsuite-bag record /scan /odom /tf -o part.mcap
    navsuite-bag info run.mcap
    navsuite-bag play run.mcap --rate 2 --clock 100 --loop
    navsuite-bag report run.mcap -o run.png
    navsuite-bag foxglove -a --port 8765        # live in Foxglove: open ws://127.0.0.1:8765

User errors (unknown topic, unreadable or malformed file, bad option values, port in use) print
one line on stderr and exit with 1; a missing optional package (``foxglove-sdk``) exits with 2;
Ctrl-C or SIGTERM ends record, play and foxglove cleanly (the file is closed with its summary,
the server is stopped) and exits with 0.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from pathlib import Path

from navsuite_tools.bag.reader import BagError
from ros_tools.dds import keep_dds_local
from ros_tools.runtime.executor import add_executor_argument


def _record(args: argparse.Namespace) -> int:
    from navsuite_tools.bag.recorder import RecordOptions, run_record

    options = RecordOptions(
        output=Path(args.output), topics=tuple(args.topics), all_topics=args.all, regex=args.regex,
        exclude_regex=args.exclude_regex, include_hidden=args.include_hidden_topics,
        max_duration=args.max_duration, use_sim_time=args.use_sim_time, compression=args.compression,
        topic_timeout=args.topic_timeout, executor=args.executor,
    )
    run_record(options)
    return 0


def _foxglove(args: argparse.Namespace) -> int:
    from navsuite_tools.bag.foxglove_live import (
        DISCOVERY_PERIOD,
        FoxgloveOptions,
        SdkMissingError,
        run_foxglove,
    )
    from navsuite_tools.bag.recorder import RecordOptions

    selection = RecordOptions(
        output=Path(os.devnull), topics=tuple(args.topics), all_topics=args.all, regex=args.regex,
        exclude_regex=args.exclude_regex, include_hidden=args.include_hidden_topics,
        use_sim_time=args.use_sim_time, discovery_period=DISCOVERY_PERIOD, executor=args.executor,
    )
    options = FoxgloveOptions(selection=selection, host=args.host, port=args.port)
    try:
        run_foxglove(options)
    except SdkMissingError as exc:
        print(f"navsuite-bag foxglove: {exc}", file=sys.stderr)
        return 2
    return 0


def _info(args: argparse.Namespace) -> int:
    from navsuite_tools.bag.info import format_info
    from navsuite_tools.bag.reader import BagReader

    with BagReader(args.bag) as reader:
        print(format_info(reader))
    return 0


def _play(args: argparse.Namespace) -> int:
    from navsuite_tools.bag.player import PlayOptions, run_play

    options = PlayOptions(
        bag=Path(args.bag), rate=args.rate, loop=args.loop, clock_hz=args.clock, topics=tuple(args.topics),
        delay=args.delay, wait_for_subscribers=args.wait_for_subscribers, executor=args.executor,
    )
    run_play(options)
    return 0


def _report(args: argparse.Namespace) -> int:
    from navsuite_tools.report import ReportParams, write_report

    out = Path(args.output) if args.output else Path(args.bag).with_suffix(".png")
    params = ReportParams(width_px=args.width, height_px=args.height, map_choice=args.map,
                          all_plans=not args.latest_plan_only)
    print(write_report(args.bag, out, params))
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with the five subcommands."""
    parser = argparse.ArgumentParser(
        prog="navsuite-bag",
        description="Record, inspect, replay and report on ROS 2 MCAP recordings; stream live to Foxglove.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    rec = sub.add_parser("record", help="record topics to an MCAP file")
    _add_selection_arguments(rec, "record")
    rec.add_argument("-o", "--output", required=True, help="output .mcap file (overwritten)")
    rec.add_argument("--max-duration", type=float, default=0.0, metavar="S",
                     help="stop after S seconds of (sim) time since the first message; 0 = until Ctrl-C")
    rec.add_argument("--use-sim-time", action="store_true", help="stamp messages with /clock time")
    rec.add_argument("--compression", choices=("zstd", "lz4", "none"), default="zstd")
    rec.add_argument("--topic-timeout", type=float, default=10.0, metavar="S",
                     help="listed topics must get a publisher within S wall seconds (0 = wait forever)")
    add_executor_argument(rec)
    rec.set_defaults(handler=_record)

    info = sub.add_parser("info", help="summarise a recording like ros2 bag info")
    info.add_argument("bag", help=".mcap file")
    info.set_defaults(handler=_info)

    play = sub.add_parser("play", help="republish a recording")
    play.add_argument("bag", help=".mcap file")
    play.add_argument("-r", "--rate", type=float, default=1.0, help="speed factor (default 1.0)")
    play.add_argument("-l", "--loop", action="store_true", help="replay until interrupted")
    play.add_argument("--clock", type=float, nargs="?", const=40.0, default=0.0, metavar="HZ",
                      help="publish /clock from the bag time at HZ (default 40 when given)")
    play.add_argument("--topics", nargs="+", default=[], help="replay only these topics")
    play.add_argument("-d", "--delay", type=float, default=0.0, metavar="S",
                      help="wait S seconds before playing")
    play.add_argument("--wait-for-subscribers", type=float, default=0.0, metavar="S",
                      help="wait up to S seconds until every topic has a subscriber")
    add_executor_argument(play)
    play.set_defaults(handler=_play)

    rep = sub.add_parser("report", help="draw a run report PNG from a recording")
    rep.add_argument("bag", help=".mcap file")
    rep.add_argument("-o", "--output", default="", help="PNG path (default: next to the bag)")
    rep.add_argument("--width", type=int, default=1600, help="pixels")
    rep.add_argument("--height", type=int, default=900, help="pixels")
    rep.add_argument("--map", choices=("first", "last"), default="last", help="which recorded /map to draw")
    rep.add_argument("--latest-plan-only", action="store_true", help="do not draw earlier plans")
    rep.set_defaults(handler=_report)

    fox = sub.add_parser("foxglove", help="stream topics live to Foxglove (needs foxglove-sdk)")
    _add_selection_arguments(fox, "stream")
    fox.add_argument("--host", default="127.0.0.1", help="bind address (default: %(default)s, loopback)")
    fox.add_argument("--port", type=int, default=8765, help="TCP port (default: %(default)s; 0 = any free)")
    fox.add_argument("--use-sim-time", action="store_true", help="stamp messages with /clock time")
    add_executor_argument(fox)
    fox.set_defaults(handler=_foxglove)
    return parser


def _add_selection_arguments(parser: argparse.ArgumentParser, verb: str) -> None:
    """The topic selection shared by record and foxglove (see RecordOptions)."""
    parser.add_argument("topics", nargs="*", help=f"topics to {verb}")
    parser.add_argument("-a", "--all", action="store_true",
                        help=f"{verb} all topics, also ones that appear later")
    parser.add_argument("-e", "--regex", default="",
                        help=f"also {verb} topics matching this regular expression")
    parser.add_argument("-x", "--exclude-regex", default="",
                        help=f"never {verb} topics matching this expression")
    parser.add_argument("--include-hidden-topics", action="store_true", help="with -a/-e, also hidden topics")


def _raise_interrupt(_signum: int, _frame: object) -> None:
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    """Run one subcommand; user errors become one line on stderr and exit code 1."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handler = getattr(args, "handler", None)
    if handler is None:
        parser.print_help(sys.stderr)
        return 1
    keep_dds_local()
    # A background child inherits an ignored SIGINT; restore it so supervisors can stop us.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        return int(handler(args))
    except (BagError, ValueError) as exc:
        print(f"navsuite-bag {args.command}: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
