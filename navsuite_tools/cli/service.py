"""``service list|type|call``: services in the graph, and one request/response exchange.

``service call`` prints ``requester: making request: <request>`` and ``response:`` followed by
the response, as ``ros2 service call`` does. The type may be omitted when the service exists.
"""

from __future__ import annotations

import argparse
from typing import Any

from navsuite_tools.cli.common import (
    CliError,
    Session,
    add_command,
    add_list_verb,
    add_wait_options,
    full_name,
    now_msg,
    print_names,
    visible,
    wait_for_type,
)
from ros_tools.convert import yaml_to_message
from ros_tools.types import import_type, looks_like_type_name


def register(subparsers: Any) -> None:
    """Add ``service`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "service", "list and call services")

    add_list_verb(verbs, "services", run_list)

    p = verbs.add_parser("type", help="print the type of a service")
    p.add_argument("service_name")
    add_wait_options(p)
    p.set_defaults(handler=run_type)

    p = verbs.add_parser("call", help="call a service with a request given as YAML")
    p.add_argument("service_name")
    p.add_argument("service_type", nargs="?", help="e.g. std_srvs/srv/SetBool (default: the service's type)")
    p.add_argument("values", nargs="?", default="{}", help="request fields as YAML (default: {})")
    add_wait_options(p)
    p.set_defaults(handler=run_call)


def _service_types(session: Session) -> list[tuple[str, list[str]]]:
    return session.node.get_service_names_and_types()


def run_list(args: argparse.Namespace, session: Session) -> int:
    """``service list``: listen until discovery settles, then print the visible services."""
    session.discover_graph(args.spin_time, args.timeout)
    pairs = visible(_service_types(session), args.include_hidden_services)
    print_names(pairs, args.show_types, args.count_services)
    return 0


def run_type(args: argparse.Namespace, session: Session) -> int:
    """``service type``: the type of a service once it appears."""
    name = full_name(args.service_name)
    print(wait_for_type(session, lambda: _service_types(session), name, "service", args.timeout))
    return 0


def run_call(args: argparse.Namespace, session: Session) -> int:
    """``service call``: send one request, wait (bounded) for the response and print it."""
    name = full_name(args.service_name)
    service_type, values = args.service_type, args.values
    if service_type is not None and not looks_like_type_name(service_type):
        service_type, values = None, service_type  # `call /srv '{data: true}'`: the type was omitted
    if service_type is None:
        service_type = wait_for_type(session, lambda: _service_types(session), name, "service", args.timeout)
    try:
        srv = import_type(service_type, "srv")
        request = yaml_to_message(srv.Request, values, now=lambda: now_msg(session))
    except ValueError as exc:
        raise CliError(str(exc)) from None
    client = session.node.create_client(srv, name)
    session.spin_until(client.service_is_ready, args.timeout, f"service '{name}' to become available")
    print(f"requester: making request: {request!r}\n", flush=True)
    response = session.wait_future(client.call_async(request), args.timeout, f"the response of '{name}'")
    print(f"response:\n{response!r}\n", flush=True)
    return 0
