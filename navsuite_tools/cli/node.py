"""``node list|info``: the nodes in the graph and each node's topics, services and actions.

``node info`` prints the sections of ``ros2 node info`` (Subscribers, Publishers, Service
Servers, Service Clients, Action Servers, Action Clients), hiding the ``_action`` topics and
services that implement actions, as ros2 does.
"""

from __future__ import annotations

import argparse
from typing import Any

from rclpy.action.graph import (
    get_action_client_names_and_types_by_node,
    get_action_server_names_and_types_by_node,
)

from navsuite_tools.cli.common import (
    Session,
    add_command,
    add_wait_options,
    node_names,
    visible,
    wait_for_node,
)


def register(subparsers: Any) -> None:
    """Add ``node`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "node", "list nodes and show what they offer")

    p = verbs.add_parser("list", help="list the nodes in the graph")
    p.add_argument("-a", "--all", action="store_true", help="include hidden nodes (names starting with _)")
    p.add_argument("-c", "--count-nodes", action="store_true", help="only print the number of nodes")
    add_wait_options(p)
    p.set_defaults(handler=run_list)

    p = verbs.add_parser("info", help="publishers, subscribers, services and actions of a node")
    p.add_argument("node_name")
    p.add_argument("--include-hidden", action="store_true", help="include hidden topics and services")
    add_wait_options(p)
    p.set_defaults(handler=run_info)


def run_list(args: argparse.Namespace, session: Session) -> int:
    """``node list``: listen until discovery settles, then print fully qualified node names."""
    session.discover_graph(args.spin_time, args.timeout)
    names = node_names(session, include_hidden=args.all)
    if args.count_nodes:
        print(len(names))
    else:
        for name in names:
            print(name)
    return 0


def node_sections(session: Session, name: str, namespace: str, include_hidden: bool) -> dict[str, list[str]]:
    """Section title → ``name: type`` lines, in ``ros2 node info`` order."""
    node = session.node
    queries = {
        "Subscribers": node.get_subscriber_names_and_types_by_node,
        "Publishers": node.get_publisher_names_and_types_by_node,
        "Service Servers": node.get_service_names_and_types_by_node,
        "Service Clients": node.get_client_names_and_types_by_node,
    }
    sections = {
        title: visible(query(name, namespace), include_hidden) for title, query in queries.items()
    }
    sections["Action Servers"] = sorted(get_action_server_names_and_types_by_node(node, name, namespace))
    sections["Action Clients"] = sorted(get_action_client_names_and_types_by_node(node, name, namespace))
    return {
        title: [f"{entity}: {', '.join(types)}" for entity, types in pairs]
        for title, pairs in sections.items()
    }


def run_info(args: argparse.Namespace, session: Session) -> int:
    """``node info``: wait for the node, listen ``--spin-time`` seconds, print its sections."""
    name, namespace = wait_for_node(session, args.node_name, args.timeout)
    session.spin_for(args.spin_time)
    print(f"{namespace.rstrip('/')}/{name}")
    for title, lines in node_sections(session, name, namespace, args.include_hidden).items():
        print(f"  {title}:")
        for line in lines:
            print(f"    {line}")
    return 0
