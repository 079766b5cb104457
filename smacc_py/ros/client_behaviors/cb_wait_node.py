"""``CbWaitNode``: EvCbSuccess once a node of the given name is in the ROS graph (SMACC2's CbWaitNode).

``node_name`` is either a bare name (``amcl``: any namespace) or a fully qualified one
(``/robot1/amcl``). The graph is read every ``POLL_PERIOD_S`` s of machine clock (a cheap, local
query of the DDS discovery cache); EvCbFailure after ``timeout_s`` (None: wait for ever).
"""

from __future__ import annotations

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import check_name
from smacc_py.ros.context import ros_context

POLL_PERIOD_S = 0.2  # s of machine clock between two reads of the graph


def fully_qualified(name: str, namespace: str) -> str:
    """``/ns/name`` from a node's name and namespace (``/`` is the root namespace)."""
    return f"{namespace.rstrip('/')}/{name}"


class CbWaitNode(CbOutcomeBase):
    """Waits until ``node_name`` appears among the nodes this machine's node discovers."""

    def __init__(self, node_name: str, timeout_s: float | None = None) -> None:
        self.node_name = check_name("CbWaitNode", "node", node_name)
        self.set_timeout(timeout_s)
        self.set_update_period(POLL_PERIOD_S)

    def start(self) -> None:
        self.poll()

    def poll(self) -> None:
        if self.node_name in self.visible_nodes():
            self.finish(True, node=self.node_name)

    def visible_nodes(self) -> set[str]:
        """Bare and fully qualified names of every node in the graph."""
        names: set[str] = set()
        for name, namespace in ros_context(self.sm).node.get_node_names_and_namespaces():
            names.update((name, fully_qualified(name, namespace)))
        return names

    def timeout_reason(self) -> str:
        return f"CbWaitNode: node '{self.node_name}' not in the graph within {self.timeout_s:g} s"
