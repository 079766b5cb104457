"""Interface type names (``pkg/msg/Type``) and the Python classes generated for them.

Users write types the way the ros2 CLI accepts them: ``geometry_msgs/msg/Twist`` or the short
``geometry_msgs/Twist``. Messages describe their own fields with strings such as ``double``,
``sequence<geometry_msgs/Point, 10>``, ``double[9]`` or ``string<8>`` (a bounded string)
(``get_fields_and_field_types()``); :func:`parse_field_type` reads those strings so the converter
does not need rosidl_parser or rosidl_runtime_py (neither is on pip).
"""

from __future__ import annotations

import importlib
import re
from dataclasses import dataclass
from typing import Any

KINDS = ("msg", "srv", "action")
_TYPE_RE = re.compile(r"^([A-Za-z][A-Za-z0-9_]*)/(?:(msg|srv|action)/)?([A-Za-z][A-Za-z0-9_]*)$")
_SEQUENCE_RE = re.compile(r"^sequence<\s*(.+?)\s*(?:,\s*(\d+)\s*)?>$")
_ARRAY_RE = re.compile(r"^(.+)\[(\d+)\]$")
_BOUNDED_STRING_RE = re.compile(r"^(w?string)<=?(\d+)>?$")  # rclpy spells it string<N>

#: Field type names of the ROS primitives (as ``get_fields_and_field_types()`` spells them).
PRIMITIVES = frozenset({
    "boolean", "octet", "char", "wchar", "float", "double", "long double",
    "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
    "string", "wstring",
})


@dataclass(frozen=True)
class TypeName:
    """A fully qualified interface type name such as ``nav2_msgs/action/Wait``."""

    package: str
    kind: str
    name: str

    def __str__(self) -> str:
        return f"{self.package}/{self.kind}/{self.name}"


def looks_like_type_name(text: str) -> bool:
    """Whether ``text`` has the shape of a type name (used to tell a type from a YAML argument)."""
    return _TYPE_RE.match(text.strip()) is not None


def parse_type_name(text: str, kind: str = "msg") -> TypeName:
    """Parse ``pkg/kind/Type`` or ``pkg/Type``; the short form takes ``kind`` (msg, srv or action).

    Raises:
        ValueError: the text is not a type name, or names a different kind than ``kind``.
    """
    if kind not in KINDS:
        raise ValueError(f"interface kind must be one of {', '.join(KINDS)}, got '{kind}'")
    match = _TYPE_RE.match(text.strip())
    if match is None:
        raise ValueError(f"'{text}' is not a type name: expected 'package/{kind}/Type' or 'package/Type'")
    package, given_kind, name = match.groups()
    if given_kind is not None and given_kind != kind:
        article = "an" if kind == "action" else "a"
        raise ValueError(f"'{text}' is a {given_kind} type, expected {article} {kind} type")
    return TypeName(package, kind, name)


def import_type(text: str, kind: str = "msg") -> Any:
    """Import the generated Python class of a message, service or action type.

    Raises:
        ValueError: malformed name, package not installed, or no such type in the package.
    """
    type_name = parse_type_name(text, kind)
    module_name = f"{type_name.package}.{kind}"
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise ValueError(
            f"unknown {kind} type '{type_name}': cannot import {module_name} ({exc})"
        ) from None
    cls = getattr(module, type_name.name, None)
    if not isinstance(cls, type):
        raise ValueError(f"unknown {kind} type '{type_name}': {module_name} has no type '{type_name.name}'")
    return cls


def type_name_of(obj: Any) -> str:
    """The ``pkg/kind/Type`` name of a generated class or instance (from its module path)."""
    cls = obj if isinstance(obj, type) else type(obj)
    parts = cls.__module__.split(".")
    if len(parts) < 2 or parts[1] not in KINDS:
        raise ValueError(f"{cls.__module__}.{cls.__name__} is not a generated ROS interface class")
    return f"{parts[0]}/{parts[1]}/{cls.__name__}"


@dataclass(frozen=True)
class FieldType:
    """One field's type: base type plus container shape.

    Attributes:
        base: a primitive name (``double``, ``string``) or a message name (``pkg/Type``).
        container: ``""`` for a single value, ``"array"`` (fixed size) or ``"sequence"``.
        size: the array size, the sequence bound, or None for an unbounded sequence.
        string_bound: maximum length of a bounded string (``string<=N``), else None.
    """

    base: str
    container: str = ""
    size: int | None = None
    string_bound: int | None = None

    @property
    def is_message(self) -> bool:
        """Whether the base type is a nested message (not a primitive)."""
        return self.base not in PRIMITIVES

    def describe(self) -> str:
        """The type as a ROS user reads it, e.g. ``double[9]`` or ``sequence<uint8, 4>``."""
        base = self.base if self.string_bound is None else f"{self.base}<={self.string_bound}"
        if self.container == "array":
            return f"{base}[{self.size}]"
        if self.container == "sequence":
            return f"sequence<{base}>" if self.size is None else f"sequence<{base}, {self.size}>"
        return base


def parse_field_type(text: str) -> FieldType:
    """Parse a field type string from ``get_fields_and_field_types()``.

    Raises:
        ValueError: the string is not a field type this parser knows.
    """
    text = text.strip()
    container, size = "", None
    match = _SEQUENCE_RE.match(text)
    if match is not None:
        container, text = "sequence", match.group(1)
        size = int(match.group(2)) if match.group(2) else None
    else:
        match = _ARRAY_RE.match(text)
        if match is not None:
            container, text, size = "array", match.group(1), int(match.group(2))
    string_bound = None
    match = _BOUNDED_STRING_RE.match(text)
    if match is not None:
        text, string_bound = match.group(1), int(match.group(2))
    if text not in PRIMITIVES and "/" not in text:
        raise ValueError(f"unrecognised field type '{text}'")
    return FieldType(text, container, size, string_bound)
