"""Node status and node kind, with the same values and meaning as BehaviorTree.CPP 4.

Why a separate module: every other part of the engine (nodes, controls, exporters, the ROS
layer's snapshot publisher) speaks these two small enums, and they must not depend on each other.
"""

from __future__ import annotations

import enum


class NodeStatus(enum.Enum):
    """What a node reports after a tick (``BT::NodeStatus``)."""

    IDLE = "IDLE"
    """Not started, or reset by its parent after it completed or was halted."""
    RUNNING = "RUNNING"
    """Started and not finished; the parent ticks it again on the next tick."""
    SUCCESS = "SUCCESS"
    """Finished successfully."""
    FAILURE = "FAILURE"
    """Finished unsuccessfully."""
    SKIPPED = "SKIPPED"
    """Did not run this tick (BT.CPP 4); the node itself stays IDLE, only the parent sees SKIPPED."""

    @property
    def is_active(self) -> bool:
        """True unless IDLE or SKIPPED (``BT::isStatusActive``)."""
        return self not in (NodeStatus.IDLE, NodeStatus.SKIPPED)

    @property
    def is_completed(self) -> bool:
        """True for SUCCESS and FAILURE (``BT::isStatusCompleted``)."""
        return self in (NodeStatus.SUCCESS, NodeStatus.FAILURE)


class NodeKind(enum.Enum):
    """The five node categories of BT.CPP (``BT::NodeType``), used by validation and display."""

    ACTION = "Action"
    CONDITION = "Condition"
    CONTROL = "Control"
    DECORATOR = "Decorator"
    SUBTREE = "SubTree"
