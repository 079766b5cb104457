"""``param list|get|set|dump``: a node's parameters through its rcl_interfaces parameter services.

Uses :class:`rclpy.parameter_client.AsyncParameterClient`. Values given to ``set`` are read as
YAML, as ``ros2 param set`` does (``true`` is a bool, ``3`` an integer, ``[1.0, 2.0]`` a double
array). ``dump`` prints the ``/node: ros__parameters:`` YAML that ``--params-file`` accepts.
"""

from __future__ import annotations

import argparse
from typing import Any

from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType
from rclpy.parameter import get_parameter_value, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient

from navsuite_tools.cli.common import (
    CliError,
    Session,
    add_command,
    add_wait_options,
    node_names,
    wait_for_node,
)
from ros_tools.convert import dump_yaml

#: ParameterType → the words ``ros2 param get`` prints before the value.
VALUE_LABELS = {
    ParameterType.PARAMETER_BOOL: "Boolean value is:",
    ParameterType.PARAMETER_INTEGER: "Integer value is:",
    ParameterType.PARAMETER_DOUBLE: "Double value is:",
    ParameterType.PARAMETER_STRING: "String value is:",
    ParameterType.PARAMETER_BYTE_ARRAY: "Byte values are:",
    ParameterType.PARAMETER_BOOL_ARRAY: "Boolean values are:",
    ParameterType.PARAMETER_INTEGER_ARRAY: "Integer values are:",
    ParameterType.PARAMETER_DOUBLE_ARRAY: "Double values are:",
    ParameterType.PARAMETER_STRING_ARRAY: "String values are:",
}


def register(subparsers: Any) -> None:
    """Add ``param`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "param", "list, get, set and dump node parameters")

    p = verbs.add_parser("list", help="list the parameters of one node or of every node")
    p.add_argument("node_name", nargs="?")
    add_wait_options(p)
    p.set_defaults(handler=run_list)

    p = verbs.add_parser("get", help="print a parameter's value")
    p.add_argument("node_name")
    p.add_argument("parameter_name")
    add_wait_options(p)
    p.set_defaults(handler=run_get)

    p = verbs.add_parser("set", help="set a parameter (the value is read as YAML)")
    p.add_argument("node_name")
    p.add_argument("parameter_name")
    p.add_argument("value")
    add_wait_options(p)
    p.set_defaults(handler=run_set)

    p = verbs.add_parser("dump", help="print a node's parameters as a ros__parameters YAML file")
    p.add_argument("node_name")
    add_wait_options(p)
    p.set_defaults(handler=run_dump)


def _client(session: Session, node_name: str, timeout: float) -> tuple[str, AsyncParameterClient]:
    name, namespace = wait_for_node(session, node_name, timeout)
    target = f"{namespace.rstrip('/')}/{name}"
    client = AsyncParameterClient(session.node, target)
    session.spin_until(client.services_are_ready, timeout, f"the parameter services of '{target}'")
    return target, client


def _names(session: Session, target: str, client: AsyncParameterClient, timeout: float) -> list[str]:
    response = session.wait_future(client.list_parameters(), timeout, f"the parameter list of '{target}'")
    return sorted(response.result.names)


def _values(session: Session, target: str, client: AsyncParameterClient, names: list[str],
            timeout: float) -> list[Any]:
    response = session.wait_future(client.get_parameters(names), timeout, f"the parameters of '{target}'")
    return list(response.values)


def run_list(args: argparse.Namespace, session: Session) -> int:
    """``param list``: parameter names of one node, or of every visible node under its name."""
    if args.node_name is not None:
        target, client = _client(session, args.node_name, args.timeout)
        for name in _names(session, target, client, args.timeout):
            print(f"  {name}")
        return 0
    session.discover_graph(args.spin_time, args.timeout)
    for node in node_names(session):
        namespace, _, short = node.rpartition("/")
        services = session.node.get_service_names_and_types_by_node(short, namespace or "/")
        if not any(name == f"{node}/list_parameters" for name, _ in services):
            continue  # a node started without parameter services
        client = AsyncParameterClient(session.node, node)
        session.spin_until(client.services_are_ready, args.timeout, f"the parameter services of '{node}'")
        print(f"{node}:")
        for name in _names(session, node, client, args.timeout):
            print(f"  {name}")
    return 0


def run_get(args: argparse.Namespace, session: Session) -> int:
    """``param get``: ``<Type> value is: <value>``; an unset parameter is an error."""
    target, client = _client(session, args.node_name, args.timeout)
    values = _values(session, target, client, [args.parameter_name], args.timeout)
    if not values or values[0].type == ParameterType.PARAMETER_NOT_SET:
        raise CliError(f"Parameter not set: '{args.parameter_name}' on node '{target}'")
    print(f"{VALUE_LABELS[values[0].type]} {parameter_value_to_python(values[0])}")
    return 0


def run_set(args: argparse.Namespace, session: Session) -> int:
    """``param set``: ``Set parameter successful``, or ``Set parameter failed: <reason>`` and exit 1."""
    target, client = _client(session, args.node_name, args.timeout)
    parameter = ParameterMsg(name=args.parameter_name, value=get_parameter_value(args.value))
    response = session.wait_future(client.set_parameters([parameter]), args.timeout,
                                   f"'{target}' to set '{args.parameter_name}'")
    result = response.results[0]
    if not result.successful:
        reason = f": {result.reason}" if result.reason else ""
        raise CliError(f"Set parameter failed{reason}")
    print("Set parameter successful")
    return 0


def nest_parameters(flat: dict[str, Any]) -> dict[str, Any]:
    """Dotted parameter names as nested mappings (``a.b: 1`` → ``a: {b: 1}``), as in params files.

    A name that is both a value and a prefix of another name keeps its dotted remainder as a key.
    """
    nested: dict[str, Any] = {}
    for name in sorted(flat):
        level = nested
        parts = name.split(".")
        for index, part in enumerate(parts[:-1]):
            child = level.setdefault(part, {})
            if not isinstance(child, dict):
                parts = [*parts[:index], ".".join(parts[index:])]
                break
            level = child
        level[parts[-1]] = flat[name]
    return nested


def run_dump(args: argparse.Namespace, session: Session) -> int:
    """``param dump``: every parameter of the node as ``/node: ros__parameters: ...`` YAML."""
    target, client = _client(session, args.node_name, args.timeout)
    names = _names(session, target, client, args.timeout)
    values = _values(session, target, client, names, args.timeout) if names else []
    flat = {name: parameter_value_to_python(value) for name, value in zip(names, values, strict=True)}
    print(dump_yaml({target: {"ros__parameters": nest_parameters(flat)}}), end="")
    return 0
