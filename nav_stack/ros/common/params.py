"""Bind a core's frozen parameter dataclass to ROS parameters with Nav2's names.

Each core keeps its parameters in one frozen dataclass whose field names and defaults follow Nav2.
A node declares every field as a ROS parameter (optionally under a prefix such as
``"FollowPath."``), so values come from a ``ros__parameters`` YAML file or ``--ros-args -p``, and
builds the dataclass from the result. An invalid value fails with a message that names the node,
the parameter and the value. ``on_dataclass_update`` lets a node take changes at run time.

A Nav2 parameter the stack accepts (so a Nav2 file loads) but never reads is listed in its dataclass's
``IGNORED`` class variable (field name -> why it has no effect); the binder says so once per node and
dataclass, at startup, with the names and values (docs/nav2-differences.md lists them too).
"""

from __future__ import annotations

import dataclasses
import typing
import weakref
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

import yaml
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter

T = TypeVar("T")

# (dataclass, prefix) pairs whose ignored parameters a node has already reported: one warning per
# node and dataclass, not one per configure.
_REPORTED: weakref.WeakKeyDictionary[Node, set[tuple[type, str]]] = weakref.WeakKeyDictionary()


def ignored_parameters(cls: type) -> Mapping[str, str]:
    """``cls.IGNORED``: the Nav2 parameters ``cls`` accepts and never reads, each with the reason."""
    ignored: Mapping[str, str] = getattr(cls, "IGNORED", {})
    return ignored


def _report_ignored(node: Node, cls: type, prefix: str, values: Mapping[str, Any]) -> None:
    """Warn once per node and dataclass that ``cls``'s ignored parameters have no effect."""
    ignored = ignored_parameters(cls)
    reported = _REPORTED.setdefault(node, set())
    if not ignored or (cls, prefix) in reported:
        return
    reported.add((cls, prefix))
    listed = "; ".join(f"{prefix}{name}={values[name]!r} ({why})" for name, why in ignored.items())
    node.get_logger().warning(f"parameters accepted for Nav2 compatibility and not read: {listed}")


def _ros_default(value: Any) -> Any:
    """ROS parameters hold scalars, strings and homogeneous lists; tuples become lists."""
    if isinstance(value, tuple):
        return [_ros_default(v) for v in value]
    return value


def _coerce(value: Any, annotation: Any) -> Any:
    """Convert a ROS parameter value back to the dataclass field's type.

    Lists become tuples, ints become floats where a float is expected (YAML ``width: 3``), and a
    string where a tuple is expected is parsed as YAML: Nav2 writes footprints as
    ``footprint: "[[0.2, 0.2], [0.2, -0.2], ...]"``.
    """
    origin = typing.get_origin(annotation)
    if annotation is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if origin is tuple and isinstance(value, str):
        value = yaml.safe_load(value) if value.strip() else []
    if origin is tuple and isinstance(value, list | tuple):
        args = typing.get_args(annotation)
        inner = args[0] if args else Any
        if inner is tuple or typing.get_origin(inner) is tuple:  # e.g. a footprint of (x, y) points
            return tuple(tuple(v) for v in value)
        return tuple(_coerce(v, inner) for v in value)
    return value


def declare_dataclass(node: Node, cls: type[T], prefix: str = "", **overrides: Any) -> T:
    """Declare every field of ``cls`` as ``<prefix><field>`` on ``node`` and build an instance.

    ``overrides`` replace a field's default (not a value set by the user). Raises ValueError naming
    the node, parameter and value when the dataclass rejects a value.
    """
    hints = typing.get_type_hints(cls)
    values: dict[str, Any] = {}
    for field in dataclasses.fields(cls):  # type: ignore[arg-type]
        if not field.init:
            continue
        if field.name in overrides:
            default = overrides[field.name]
        elif field.default is not dataclasses.MISSING:
            default = field.default
        elif field.default_factory is not dataclasses.MISSING:
            default = field.default_factory()
        else:
            raise TypeError(f"{cls.__name__}.{field.name} needs a default to be a ROS parameter")
        name = prefix + field.name
        if not node.has_parameter(name):
            ros_default = _ros_default(default)
            # No type to infer, or a float a YAML file may spell as an int: let the value decide
            # the type, and _coerce() checks it against the dataclass.
            if ros_default is None or ros_default == [] or isinstance(ros_default, float):
                node.declare_parameter(name, ros_default, ParameterDescriptor(dynamic_typing=True))
            else:
                node.declare_parameter(name, ros_default)
        values[field.name] = _coerce(node.get_parameter(name).value, hints.get(field.name, Any))
    try:
        built = cls(**values)
    except (TypeError, ValueError) as error:
        shown = ", ".join(f"{prefix}{k}={v!r}" for k, v in values.items())
        raise ValueError(
            f"{node.get_name()}: invalid parameters for {cls.__name__}: {error} ({shown})"
        ) from error
    _report_ignored(node, cls, prefix, values)
    return built


def on_dataclass_update(node: Node, cls: type[T], prefix: str, current: Callable[[], T],
                        apply: Callable[[T], None], renames: Mapping[str, str] | None = None
                        ) -> Callable[[list[Parameter]], SetParametersResult]:
    """Take run-time changes of ``<prefix><field>`` parameters (``ros2 param set``), as Nav2's
    plugins do in their ``dynamicParametersCallback``.

    The changed fields are applied to ``current()`` with ``dataclasses.replace``, so the dataclass
    validates them together; ``apply`` receives the new instance. A rejected value leaves the old
    parameters in place, and the reason names the node, the parameter and the value. ``renames`` maps
    fields declared under Nav2 spellings (DWB's ``PathAlign.scale``). Returns the callback, for
    ``node.remove_on_set_parameters_callback`` at cleanup.
    """
    hints = typing.get_type_hints(cls)
    spelled = renames or {}
    fields = {prefix + spelled.get(f.name, f.name): f.name
              for f in dataclasses.fields(cls) if f.init}  # type: ignore[arg-type]

    def check_and_apply(parameters: list[Parameter]) -> SetParametersResult:
        changes = {fields[p.name]: _coerce(p.value, hints.get(fields[p.name], Any))
                   for p in parameters if p.name in fields}
        if not changes:
            return SetParametersResult(successful=True)
        try:
            updated = dataclasses.replace(current(), **changes)  # type: ignore[type-var]
        except (TypeError, ValueError) as error:
            shown = ", ".join(f"{prefix}{spelled.get(k, k)}={v!r}" for k, v in changes.items())
            return SetParametersResult(successful=False, reason=f"{node.get_name()}: {error} ({shown})")
        apply(updated)
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(check_and_apply)
    return check_and_apply
