"""Exceptions of the behaviour-tree engine.

Definition errors (bad XML, unknown node, missing or malformed port) are raised while a tree is
loaded and name the file, line and node, so a user can fix the XML without reading engine code.
Errors during a tick are programming errors of a node (a leaf returning IDLE, a port read that
the XML never wired) and name the node's path in the tree.
"""

from __future__ import annotations


class BtError(Exception):
    """Root of all behaviour-tree engine errors."""


class BtLoadError(BtError, ValueError):
    """A tree definition cannot be loaded.

    Attributes:
        source: file path (or ``<string>``) the definition came from.
        line: 1-based line of the offending element, or 0 when not tied to one element.
        node: ``<Tag name="...">`` of the offending element, or "" when not tied to one.
        reason: the message without the location prefix.
    """

    def __init__(self, reason: str, source: str = "<string>", line: int = 0, node: str = "") -> None:
        self.source = source
        self.line = line
        self.node = node
        self.reason = reason
        where = f"{source}:{line}" if line else source
        super().__init__(f"{where}: {node}: {reason}" if node else f"{where}: {reason}")


class BtRuntimeError(BtError, RuntimeError):
    """A node misbehaved while ticking (wrong status, unwired port, bad blackboard value)."""


class BtPortError(BtRuntimeError, KeyError):
    """An input port could not be read or converted at tick time."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
