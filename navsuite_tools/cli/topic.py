"""``topic list|info|echo|hz|pub``: the ``ros2 topic`` verbs on rclpy's graph API.

Output follows ros2topic: echo prints each message as YAML followed by ``---``; pub prints
``publisher: beginning loop`` and ``publishing #N: <message>``; hz prints
``average rate: R`` and ``min: ..s max: ..s std dev: ..s window: N`` once a second.
"""

from __future__ import annotations

import argparse
import math
import time
from collections import deque
from typing import Any

from rclpy.duration import Duration

from navsuite_tools.cli.common import (
    CliError,
    Session,
    add_command,
    add_list_verb,
    add_qos_options,
    add_wait_options,
    full_name,
    now_msg,
    print_names,
    qos_from_args,
    visible,
    wait_for_type,
)
from ros_tools.convert import (
    dump_yaml,
    field_value,
    message_to_dict,
    message_to_yaml,
    to_csv,
    yaml_to_message,
)
from ros_tools.types import import_type, type_name_of


def register(subparsers: Any) -> None:
    """Add ``topic`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "topic", "inspect, echo and publish topics")

    add_list_verb(verbs, "topics", run_list)

    p = verbs.add_parser("info", help="type and publisher/subscription counts of a topic")
    p.add_argument("topic_name")
    p.add_argument("-v", "--verbose", action="store_true", help="show each endpoint's node and QoS")
    add_wait_options(p)
    p.set_defaults(handler=run_info)

    p = verbs.add_parser("echo", help="print the messages of a topic as YAML")
    p.add_argument("topic_name")
    p.add_argument("message_type", nargs="?", help="e.g. std_msgs/msg/String (default: the topic's type)")
    p.add_argument("--once", action="store_true", help="print the first message and exit")
    p.add_argument("--field", help="print only this (dotted) field, e.g. pose.position")
    p.add_argument("--no-arr", action="store_true", help="summarise arrays instead of printing them")
    p.add_argument("--csv", action="store_true", help="print each message as one comma-separated line")
    add_qos_options(p, default_depth=10)
    add_wait_options(p)
    p.set_defaults(handler=run_echo)

    p = verbs.add_parser("hz", help="print the rate at which a topic is published")
    p.add_argument("topic_name")
    p.add_argument("-w", "--window", type=int, default=10000, help="messages in the statistics window")
    add_qos_options(p, default_depth=10)
    add_wait_options(p)
    p.set_defaults(handler=run_hz)

    p = verbs.add_parser("pub", help="publish a message given as YAML")
    p.add_argument("topic_name")
    p.add_argument("message_type", help="e.g. geometry_msgs/msg/Twist")
    p.add_argument("values", nargs="?", default="{}", help="message fields as YAML (default: {})")
    p.add_argument("-r", "--rate", type=float, default=1.0, help="publishing rate in Hz (default 1)")
    p.add_argument("-1", "--once", action="store_true", help="publish one message and exit")
    p.add_argument("-t", "--times", type=int, default=0, help="publish this many messages and exit")
    p.add_argument("-p", "--print", dest="print_nth", type=int, default=1,
                   help="print every N-th published message (0: never)")
    p.add_argument("-w", "--wait-matching-subscriptions", type=int, default=None,
                   help="wait for this many subscriptions first (default 1 with --once/--times, else 0)")
    p.add_argument("--keep-alive", type=float, default=0.1, help="seconds to stay up after the last message")
    add_qos_options(p, default_depth=1)
    add_wait_options(p)
    p.set_defaults(handler=run_pub)


def _topic_types(session: Session) -> list[tuple[str, list[str]]]:
    return session.node.get_topic_names_and_types()


def run_list(args: argparse.Namespace, session: Session) -> int:
    """``topic list``: listen until discovery settles, then print the visible topics."""
    session.discover_graph(args.spin_time, args.timeout)
    pairs = visible(_topic_types(session), args.include_hidden_topics)
    print_names(pairs, args.show_types, args.count_topics)
    return 0


def run_info(args: argparse.Namespace, session: Session) -> int:
    """``topic info``: the type, then publishers and subscriptions (with QoS when verbose)."""
    topic = full_name(args.topic_name)
    wait_for_type(session, lambda: _topic_types(session), topic, "topic", args.timeout)
    session.spin_for(args.spin_time)  # let the remaining endpoints of the topic be discovered
    types = next(types for name, types in _topic_types(session) if name == topic)
    publishers = session.node.get_publishers_info_by_topic(topic)
    subscriptions = session.node.get_subscriptions_info_by_topic(topic)
    separator = "\n" if args.verbose else ""
    print(f"Type: {'; '.join(types)}{separator}")
    print(f"Publisher count: {len(publishers)}{separator}")
    for endpoint in publishers if args.verbose else []:
        print(f"{endpoint}\n")
    print(f"Subscription count: {len(subscriptions)}{separator}")
    for endpoint in subscriptions if args.verbose else []:
        print(f"{endpoint}\n")
    return 0


def resolve_message_class(session: Session, topic: str, given: str | None, timeout: float) -> Any:
    """The message class for ``topic``: the given type, or the type the graph reports.

    Raises:
        CliError: unknown type, topic never appeared, or the topic has a different type.
    """
    if given is None:
        given = wait_for_type(session, lambda: _topic_types(session), topic, "topic", timeout)
    try:
        cls = import_type(given, "msg")
    except ValueError as exc:
        raise CliError(str(exc)) from None
    known = next((types for name, types in _topic_types(session) if name == topic), [])
    if known and type_name_of(cls) not in known:
        raise CliError(f"topic '{topic}' has type {'; '.join(known)}, not {type_name_of(cls)}")
    return cls


def _format_plain(value: Any) -> str:
    if isinstance(value, (dict, list)):
        return dump_yaml(value).rstrip("\n")
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def run_echo(args: argparse.Namespace, session: Session) -> int:
    """``topic echo``: print every message (or one field of it) followed by ``---``."""
    topic = full_name(args.topic_name)
    cls = resolve_message_class(session, topic, args.message_type, args.timeout)
    received: list[int] = [0]

    def on_message(msg: Any) -> None:
        if args.once and received[0]:
            return
        received[0] += 1
        if args.field is not None:
            text = _format_plain(field_value(msg, args.field))
        elif args.csv:
            text = to_csv(message_to_dict(msg))
        else:
            text = message_to_yaml(msg, no_arr=args.no_arr).rstrip("\n")
        print(text if args.csv else f"{text}\n---", flush=True)

    if args.field is not None:
        try:
            field_value(cls(), args.field)  # a bad --field is an error now, not at the first message
        except ValueError as exc:
            raise CliError(str(exc)) from None
    session.node.create_subscription(cls, topic, on_message, qos_from_args(args, session, topic))
    while not (args.once and received[0]):
        session.spin_once(0.1)
    return 0


def rate_statistics(arrivals: deque[float]) -> tuple[float, float, float, float]:
    """(average rate Hz, min period s, max period s, period std dev s) of arrival times in s."""
    periods = [later - earlier for earlier, later in zip(arrivals, list(arrivals)[1:], strict=False)]
    mean = sum(periods) / len(periods)
    std = math.sqrt(sum((p - mean) ** 2 for p in periods) / len(periods))
    return (1.0 / mean if mean > 0 else math.inf), min(periods), max(periods), std


def run_hz(args: argparse.Namespace, session: Session) -> int:
    """``topic hz``: once a second, the rate statistics over the last ``--window`` messages."""
    if args.window < 2:
        raise CliError(f"--window must be at least 2 messages, got {args.window}")
    topic = full_name(args.topic_name)
    cls = resolve_message_class(session, topic, None, args.timeout)
    arrivals: deque[float] = deque(maxlen=args.window)
    reported = [0.0]

    def on_message(_raw: bytes) -> None:
        arrivals.append(time.monotonic())

    def report() -> None:
        if len(arrivals) < 2 or arrivals[-1] == reported[0]:
            print("no new messages" if arrivals else f"waiting for messages on '{topic}'", flush=True)
            return
        reported[0] = arrivals[-1]
        rate, low, high, std = rate_statistics(arrivals)
        print(f"average rate: {rate:.3f}\n\tmin: {low:.3f}s max: {high:.3f}s std dev: {std:.5f}s "
              f"window: {len(arrivals)}", flush=True)

    session.node.create_subscription(cls, topic, on_message, qos_from_args(args, session, topic), raw=True)
    session.node.create_timer(1.0, report)
    while True:
        session.spin_once(0.1)


def run_pub(args: argparse.Namespace, session: Session) -> int:
    """``topic pub``: publish the YAML message at ``--rate`` Hz, ``--times`` times or forever."""
    topic = full_name(args.topic_name)
    if args.rate <= 0:
        raise CliError(f"--rate must be positive, got {args.rate}")
    cls = resolve_message_class(session, topic, args.message_type, args.timeout)
    try:
        # Malformed values fail before anything starts.
        yaml_to_message(cls, args.values, now=lambda: now_msg(session))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    times = 1 if args.once else args.times
    wanted = args.wait_matching_subscriptions
    wanted = (1 if times else 0) if wanted is None else wanted
    publisher = session.node.create_publisher(cls, topic, qos_from_args(args))
    if wanted:
        session.spin_until(lambda: publisher.get_subscription_count() >= wanted, args.timeout,
                           f"{wanted} matching subscription(s) on '{topic}'")
    print("publisher: beginning loop", flush=True)
    count = 0
    next_time = time.monotonic()
    while not times or count < times:
        session.spin_once(max(0.0, next_time - time.monotonic()))
        if time.monotonic() < next_time:
            continue
        # Built anew each time so that 'now' and 'auto' stamps are fresh.
        msg = yaml_to_message(cls, args.values, now=lambda: now_msg(session))
        publisher.publish(msg)
        count += 1
        if args.print_nth and count % args.print_nth == 0:
            print(f"publishing #{count}: {msg!r}\n", flush=True)
        next_time += 1.0 / args.rate
    # Reliable subscribers have every message before we leave (bounded for lost subscribers).
    publisher.wait_for_all_acked(Duration(seconds=args.timeout))
    session.spin_for(args.keep_alive)
    return 0
