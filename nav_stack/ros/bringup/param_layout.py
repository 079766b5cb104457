"""Declaring a core dataclass's fields under Nav2's parameter names when they are not one flat prefix.

Why: :func:`declare_dataclass` binds ``<prefix><field>`` for every field. Some Nav2 layouts split a
component's knobs (the obstacle layer's per-source ``<layer>.<source>.<field>``), rename them
(DWB critics: ``FollowPath.BaseObstacle.scale``) or take some from the server rather than from
parameters (RPP's inscribed radius comes from the costmap). These helpers declare a subset of
fields, optionally renamed, with the dataclass defaults (still the only copy), and build the
dataclass with an error naming the node and the values.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from typing import Any

from rclpy.node import Node

from nav_stack.ros.common.params import declare_dataclass


def param(node: Node, name: str, default: Any) -> Any:
    """Value of parameter ``name``, declared with ``default`` unless a previous configure declared it."""
    if not node.has_parameter(name):
        node.declare_parameter(name, default)
    return node.get_parameter(name).value


def declare_fields(
    node: Node, cls: type, names: Iterable[str], prefix: str, **overrides: Any
) -> dict[str, Any]:
    """Declare only the fields ``names`` of dataclass ``cls`` as ``<prefix><field>``; return their values."""
    wanted = set(names)
    view = dataclasses.make_dataclass(
        f"{cls.__name__}Fields",
        [(f.name, f.type, dataclasses.field(default=f.default)) for f in dataclasses.fields(cls)
         if f.name in wanted],
        frozen=True,
    )
    view.__module__ = cls.__module__  # so the string annotations resolve in the core's module
    subset = {k: v for k, v in overrides.items() if k in wanted}
    return dataclasses.asdict(declare_dataclass(node, view, prefix, **subset))


def declare_renamed(node: Node, cls: type, prefix: str, renames: Mapping[str, str]) -> dict[str, Any]:
    """Declare fields of ``cls`` named in ``renames`` as ``<prefix><renames[field]>`` (Nav2 spelling)."""
    defaults = {f.name: f.default for f in dataclasses.fields(cls)}
    values = {}
    for field, name in renames.items():
        value = param(node, prefix + name, defaults[field])
        as_float = isinstance(defaults[field], float) and isinstance(value, int)
        values[field] = float(value) if as_float else value
    return values


def build(node: Node, cls: type, values: Mapping[str, Any], what: str) -> Any:
    """``cls(**values)``, with an error naming the node and parameters when the values are refused."""
    try:
        return cls(**values)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{node.get_name()}: invalid {what} parameters: {error} ({dict(values)})") from error
