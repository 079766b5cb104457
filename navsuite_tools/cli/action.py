"""``action list|info|send_goal``: actions in the graph, and one goal from start to result.

``send_goal`` prints what ``ros2 action send_goal`` prints: the goal, ``Goal accepted with ID:``
(32 hex digits), each feedback as YAML with ``--feedback``, the result and ``Goal finished with
status: SUCCEEDED``. Ctrl-C while the goal runs cancels it. The exit code is 0 only when the goal
succeeded, so scripts can branch on it.
"""

from __future__ import annotations

import argparse
from typing import Any

from action_msgs.msg import GoalStatus
from rclpy.action.client import ActionClient
from rclpy.action.graph import (
    get_action_client_names_and_types_by_node,
    get_action_names_and_types,
    get_action_server_names_and_types_by_node,
)

from navsuite_tools.cli.common import (
    CliError,
    Session,
    add_command,
    add_list_verb,
    add_wait_options,
    full_name,
    node_names,
    now_msg,
    print_names,
    wait_for_type,
)
from ros_tools.convert import message_to_yaml, yaml_to_message
from ros_tools.runtime.actions import send_until_acknowledged
from ros_tools.types import import_type

#: GoalStatus code → the name ros2 prints (SUCCEEDED, ABORTED, ...).
STATUS_NAMES = {
    getattr(GoalStatus, attr): attr.removeprefix("STATUS_")
    for attr in dir(GoalStatus) if attr.startswith("STATUS_")
}


def register(subparsers: Any) -> None:
    """Add ``action`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "action", "list actions and send goals")

    add_list_verb(verbs, "actions", run_list, hidden=False)

    p = verbs.add_parser("info", help="the servers and clients of an action")
    p.add_argument("action_name")
    p.add_argument("-t", "--show-types", action="store_true", help="also print the action type")
    add_wait_options(p)
    p.set_defaults(handler=run_info)

    p = verbs.add_parser("send_goal", help="send a goal given as YAML and wait for its result")
    p.add_argument("action_name")
    p.add_argument("action_type", help="e.g. nav2_msgs/action/NavigateToPose")
    p.add_argument("goal", nargs="?", default="{}", help="goal fields as YAML (default: {})")
    p.add_argument("-f", "--feedback", action="store_true", help="print the feedback messages")
    add_wait_options(p)
    p.set_defaults(handler=run_send_goal)


def run_list(args: argparse.Namespace, session: Session) -> int:
    """``action list``: listen until discovery settles, then print the actions."""
    session.discover_graph(args.spin_time, args.timeout)
    print_names(sorted(get_action_names_and_types(session.node)), args.show_types, args.count_actions)
    return 0


def run_info(args: argparse.Namespace, session: Session) -> int:
    """``action info``: which nodes serve and use the action."""
    name = full_name(args.action_name)
    wait_for_type(session, lambda: get_action_names_and_types(session.node), name, "action", args.timeout)
    session.spin_for(args.spin_time)
    servers: list[str] = []
    clients: list[str] = []
    for node in node_names(session, include_hidden=True):
        namespace, _, short = node.rpartition("/")
        for found, query in ((servers, get_action_server_names_and_types_by_node),
                             (clients, get_action_client_names_and_types_by_node)):
            for action, types in query(session.node, short, namespace or "/"):
                if action == name:
                    found.append(f"{node} [{'; '.join(types)}]" if args.show_types else node)
    print(f"Action: {name}")
    for title, nodes in (("Action clients", clients), ("Action servers", servers)):
        print(f"{title}: {len(nodes)}")
        for node in nodes:
            print(f"    {node}")
    return 0


def _indented(msg: Any) -> str:
    return "\n".join(f"    {line}" for line in message_to_yaml(msg).rstrip("\n").splitlines())


def run_send_goal(args: argparse.Namespace, session: Session) -> int:
    """``action send_goal``: send, print feedback, wait for the result; cancel on Ctrl-C."""
    name = full_name(args.action_name)
    try:
        action_type = import_type(args.action_type, "action")
        goal = yaml_to_message(action_type.Goal, args.goal, now=lambda: now_msg(session))
    except ValueError as exc:
        raise CliError(str(exc)) from None

    client = ActionClient(session.node, action_type, name)  # type: ignore[no-untyped-call]
    try:
        return _send_goal(session, client, name, goal, args.timeout, args.feedback)
    finally:
        client.destroy()  # type: ignore[no-untyped-call]


def _print_feedback(message: Any) -> None:
    print(f"Feedback:\n{_indented(message.feedback)}\n", flush=True)


def _send_goal(
    session: Session, client: ActionClient, name: str, goal: Any, timeout: float, print_feedback: bool,
) -> int:
    """Wait for the server, send the goal, print feedback and the result; cancel on Ctrl-C."""
    print("Waiting for an action server to become available...", flush=True)
    session.spin_until(client.server_is_ready, timeout, f"action server '{name}'")
    print(f"Sending goal:\n{_indented(goal)}\n", flush=True)
    # Sent again every few seconds until acknowledged: a request or its answer can be lost while DDS
    # completes the match (see ros_tools.runtime.actions.send_until_acknowledged).
    try:
        sent = send_until_acknowledged(client, goal, timeout, wait=session.wait,
                                       feedback_callback=_print_feedback if print_feedback else None)
    except TimeoutError as error:
        raise CliError(f"timed out waiting for '{name}' to accept or reject the goal: {error}") from None
    handle = session.wait_future(sent, timeout, f"'{name}' to accept or reject the goal")
    if not handle.accepted:
        print("Goal was rejected.", flush=True)
        return 1
    print(f"Goal accepted with ID: {bytes(handle.goal_id.uuid).hex()}\n", flush=True)
    result_future = handle.get_result_async()
    try:
        while not result_future.done():
            session.spin_once(0.1)
    except KeyboardInterrupt:
        print("Canceling goal...", flush=True)
        session.wait_future(handle.cancel_goal_async(), timeout, f"'{name}' to cancel the goal")
        session.spin_until(result_future.done, timeout, f"the result of the canceled goal on '{name}'")
    response = result_future.result()
    print(f"Result:\n{_indented(response.result)}\n", flush=True)
    status = STATUS_NAMES.get(response.status, str(response.status))
    print(f"Goal finished with status: {status}", flush=True)
    return 0 if response.status == GoalStatus.STATUS_SUCCEEDED else 1
