"""One /clock subscription per process, however many nodes it spins.

Why: every rclpy Node with ``use_sim_time`` subscribes to /clock through its own TimeSource. A
process holding the seven Nav2 servers and their costmap nodes therefore took seven /clock
callbacks per clock message (700 per wall second at 100 Hz and real-time factor 1), and each
callback costs a rebuild of the executor's wait set over every entity of every node. Measured on
the navigation process at idle: 561 /clock callbacks per second, about half of its 80 % CPU.

:func:`share_sim_time` keeps the subscription of the first node and moves the other nodes' ROS
clocks onto its TimeSource, which then sets the time of all of them from one message. The nodes
keep their own ``use_sim_time`` parameter; rclpy has no public API for this, so the function
relies on ``Node._time_source`` (stable since Foxy) and says so if it ever disappears.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

USE_SIM_TIME = "use_sim_time"


def _time_source(node: Any) -> Any:
    source = getattr(node, "_time_source", None)
    if source is None:
        raise RuntimeError("share_sim_time: this rclpy has no Node._time_source; "
                           "spin the nodes without sharing their clocks")
    return source


def share_sim_time(nodes: Iterable[Any]) -> int:
    """Make the sim-time nodes of ``nodes`` share one /clock subscription; returns how many were moved.

    Nodes without ``use_sim_time`` are left alone. Call it after the nodes are built and before
    spinning; timers already created keep working because each node keeps its own clock object.
    Setting ``use_sim_time`` later on a follower still switches that node's clock between ROS and
    system time (its own TimeSource keeps the parameter callback), it simply never subscribes.
    """
    sim_nodes = [node for node in nodes
                 if node.has_parameter(USE_SIM_TIME) and node.get_parameter(USE_SIM_TIME).value is True]
    if len(sim_nodes) < 2:
        return 0
    owner = _time_source(sim_nodes[0])
    for node in sim_nodes[1:]:
        _time_source(node).detach_node()  # destroys its /clock subscription
        owner.attach_clock(node.get_clock())
    return len(sim_nodes) - 1
