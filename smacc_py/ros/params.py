"""Frozen parameter dataclasses ↔ ROS parameters: declare every field with its default, read back.

Defaults live only in the dataclass; a ``node_name: ros__parameters:`` YAML (``--params-file``) or
``parameter_overrides`` change them. Tuples of floats become ``double[]`` parameters. A value of the
wrong type or shape raises ValueError naming the node, the parameter and the value, at startup.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, TypeVar

from rcl_interfaces.msg import ParameterDescriptor

if TYPE_CHECKING:
    from rclpy.node import Node

T = TypeVar("T")


def _default(field: dataclasses.Field[Any]) -> Any:
    if field.default is not dataclasses.MISSING:
        return field.default
    if field.default_factory is not dataclasses.MISSING:
        return field.default_factory()
    raise ValueError(f"parameter field {field.name} needs a default")


def _to_ros(value: Any) -> Any:
    if isinstance(value, tuple):
        return [float(v) for v in value]
    return value


def _from_ros(node: Node, name: str, default: Any, value: Any) -> Any:
    where = f"node {node.get_name()!r} parameter {name!r}"
    if isinstance(default, tuple):
        try:
            items = tuple(float(v) for v in value)
        except (TypeError, ValueError):
            raise ValueError(f"{where} must be a list of numbers, got {value!r}") from None
        if default and len(items) != len(default):
            raise ValueError(f"{where} must have {len(default)} numbers, got {list(items)!r}")
        return items
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ValueError(f"{where} must be true or false, got {value!r}")
        return value
    if isinstance(default, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{where} must be a number, got {value!r}")
        return float(value)
    if isinstance(default, int):
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"{where} must be an integer, got {value!r}")
        return value
    if isinstance(default, str) and not isinstance(value, str):
        raise ValueError(f"{where} must be a string, got {value!r}")
    return value


def declare_dataclass_params(node: Node, params_type: type[T], prefix: str = "") -> T:
    """Declare each field of ``params_type`` on ``node`` (``prefix`` + name) and build the dataclass."""
    values: dict[str, Any] = {}
    for field in dataclasses.fields(params_type):  # type: ignore[arg-type]
        name = prefix + field.name
        default = _default(field)
        if node.has_parameter(name):
            raw = node.get_parameter(name).value
        else:
            # Dynamic typing: a YAML ``[2, 0, 0]`` (integers) must still fill a double[] knob; the value
            # is checked and converted below, with an error naming the parameter.
            descriptor = ParameterDescriptor(dynamic_typing=True)
            raw = node.declare_parameter(name, _to_ros(default), descriptor).value
        values[field.name] = _from_ros(node, name, default, raw)
    try:
        return params_type(**values)
    except (TypeError, ValueError) as error:
        raise ValueError(f"node {node.get_name()!r}: invalid {params_type.__name__}: {error}") from error
