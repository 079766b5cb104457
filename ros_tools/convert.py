"""Messages ↔ plain Python values ↔ YAML (what rosidl_runtime_py offers, which pip lacks).

Plain values are what YAML can hold: dicts in field order, lists, ints, floats, bools and
strings. Arrays come out as lists whether the message holds them as numpy arrays (fixed-size
numeric arrays), ``array.array`` (numeric sequences), ``bytes`` or lists of one-byte ``bytes``
(``octet`` fields). Messages are read field by field through ``get_fields_and_field_types()``, so
constants never appear. ``builtin_interfaces`` Time and Duration are ordinary nested messages
(``sec``, ``nanosec``); when filling a message, a Time may be given as ``now`` and a
``std_msgs/Header`` as ``auto`` (a header stamped now), as ``ros2 topic pub`` allows.

Errors name the offending field by its path, e.g. ``geometry_msgs/msg/Twist.linear.x``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from typing import Any

import yaml

from ros_tools.types import FieldType, import_type, parse_field_type, type_name_of

#: Returns the current time as a ``builtin_interfaces/msg/Time`` (used for ``now`` and ``auto``).
NowFn = Callable[[], Any]

_FLOATS = frozenset({"float", "double", "long double"})
_INT_RANGES = {
    "int8": (-(2**7), 2**7 - 1), "uint8": (0, 2**8 - 1), "char": (0, 2**8 - 1), "octet": (0, 2**8 - 1),
    "int16": (-(2**15), 2**15 - 1), "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1), "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1), "uint64": (0, 2**64 - 1),
}
_STRINGS = frozenset({"string", "wstring", "wchar"})
_TIME_TYPE = "builtin_interfaces/Time"
_HEADER_TYPE = "std_msgs/Header"


@functools.cache
def message_fields(cls: Any) -> dict[str, FieldType]:
    """The fields of a generated message class, in declaration order, with parsed types."""
    getter = getattr(cls, "get_fields_and_field_types", None)
    if getter is None:
        raise ValueError(f"{cls.__module__}.{cls.__name__} is not a ROS message class")
    return {name: parse_field_type(text) for name, text in getter().items()}


# ---------------------------------------------------------------- message → plain values
def message_to_dict(msg: Any, *, no_arr: bool = False) -> dict[str, Any]:
    """Convert a message into a dict of plain values (nested dicts for nested messages).

    Args:
        msg: an instance of a generated message class.
        no_arr: replace every array and sequence by a short description, like ``ros2 topic echo
            --no-arr`` (``<sequence type: float, length: 360>``).
    """
    return {
        name: _to_plain(getattr(msg, name), ftype, no_arr)
        for name, ftype in message_fields(msg.__class__).items()
    }


def _to_plain(value: Any, ftype: FieldType, no_arr: bool) -> Any:
    if not ftype.container:
        return _element_to_plain(value, ftype, no_arr)
    if no_arr:
        if ftype.container == "array":
            return f"<array type: {ftype.base}[{ftype.size}]>"
        return f"<sequence type: {ftype.base}, length: {len(value)}>"
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if not ftype.is_message and ftype.base != "octet" and hasattr(value, "tolist"):
        return value.tolist()  # numpy arrays and array.array: fast and already plain
    return [_element_to_plain(item, ftype, no_arr) for item in value]


def _element_to_plain(value: Any, ftype: FieldType, no_arr: bool) -> Any:
    base = ftype.base
    if ftype.is_message:
        return message_to_dict(value, no_arr=no_arr)
    if isinstance(value, (bytes, bytearray)):
        return value[0] if len(value) == 1 else list(value)
    if base in _FLOATS:
        return float(value)
    if base == "boolean":
        return bool(value)
    if base in _INT_RANGES:
        return int(value)
    return str(value)


def message_to_yaml(msg: Any, *, no_arr: bool = False) -> str:
    """A message as block-style YAML in field order (the body ``ros2 topic echo`` prints)."""
    return dump_yaml(message_to_dict(msg, no_arr=no_arr))


def dump_yaml(value: Any) -> str:
    """Plain values as block-style YAML, keys in their given order."""
    return yaml.safe_dump(value, sort_keys=False, default_flow_style=False, allow_unicode=True, width=1000)


def field_value(msg: Any, dotted: str) -> Any:
    """The plain value of a (nested) field selected by a dotted path such as ``pose.position.x``.

    Raises:
        ValueError: some part of the path is not a field.
    """
    value: Any = message_to_dict(msg)
    walked = type_name_of(msg)
    for part in dotted.split("."):
        if not isinstance(value, dict) or part not in value:
            known = ", ".join(value) if isinstance(value, dict) else "none: not a message"
            raise ValueError(f"'{walked}' has no field '{part}' (fields: {known})")
        value, walked = value[part], f"{walked}.{part}"
    return value


def to_csv(value: Any) -> str:
    """Flatten plain values (dicts and lists, depth first) into one comma-separated line."""
    leaves: list[str] = []

    def walk(item: Any) -> None:
        if isinstance(item, dict):
            for child in item.values():
                walk(child)
        elif isinstance(item, list):
            for child in item:
                walk(child)
        else:
            leaves.append(str(item).lower() if isinstance(item, bool) else str(item))

    walk(value)
    return ",".join(leaves)


# ---------------------------------------------------------------- plain values → message
def parse_yaml(text: str) -> Any:
    """Parse YAML text; a syntax error becomes a one-line ValueError with line and column."""
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark is not None else ""
        raise ValueError(f"malformed YAML {text!r}: {problem}{where}") from None


def yaml_to_message(cls: type, text: str, *, now: NowFn | None = None) -> Any:
    """Build a message of class ``cls`` from a YAML mapping (empty text gives the default message)."""
    values = parse_yaml(text)
    return dict_to_message(cls, {} if values is None else values, now=now)


def dict_to_message(target: Any, values: Any, *, now: NowFn | None = None) -> Any:
    """Fill a message (or a new instance of a message class) from a mapping of field values.

    Fields not mentioned keep their current (default) values.

    Raises:
        ValueError: unknown field, wrong value type, value out of range or wrong array length;
            the message names the field path and the value.
    """
    msg = target() if isinstance(target, type) else target
    _fill(msg, values, type_name_of(msg), now)
    return msg


def _fill(msg: Any, values: Any, path: str, now: NowFn | None) -> None:
    if not isinstance(values, Mapping):
        raise ValueError(f"{path}: expected a mapping of field names to values, got {values!r}")
    fields = message_fields(msg.__class__)
    for key, value in values.items():
        if key not in fields:
            raise ValueError(f"{path}: no field '{key}' (fields: {', '.join(fields) or 'none'})")
        ftype = fields[key]
        setattr(msg, key, _from_plain(value, ftype, getattr(msg, key), f"{path}.{key}", now))


def _from_plain(value: Any, ftype: FieldType, current: Any, path: str, now: NowFn | None) -> Any:
    if not ftype.container:
        return _element_from_plain(value, ftype, current, path, now)
    if isinstance(value, (bytes, bytearray)) and ftype.base in ("octet", "uint8", "char"):
        value = list(value)
    if not isinstance(value, (list, tuple)):
        raise ValueError(f"{path}: expected a list for {ftype.describe()}, got {value!r}")
    if ftype.container == "array" and len(value) != ftype.size:
        raise ValueError(f"{path}: {ftype.describe()} needs exactly {ftype.size} values, got {len(value)}")
    if ftype.container == "sequence" and ftype.size is not None and len(value) > ftype.size:
        raise ValueError(f"{path}: {ftype.describe()} holds at most {ftype.size} values, got {len(value)}")
    element = FieldType(ftype.base, "", None, ftype.string_bound)
    cls = import_type(ftype.base) if ftype.is_message else None
    return [
        _element_from_plain(item, element, cls() if cls is not None else None, f"{path}[{index}]", now)
        for index, item in enumerate(value)
    ]


def _element_from_plain(value: Any, ftype: FieldType, current: Any, path: str, now: NowFn | None) -> Any:
    if ftype.is_message:
        if isinstance(value, type(current)):
            return value
        if value == "now" and ftype.base == _TIME_TYPE and now is not None:
            return now()
        if value == "auto" and ftype.base == _HEADER_TYPE and now is not None:
            value = {"stamp": now()}
        _fill(current, value, path, now)
        return current
    return _primitive(value, ftype, path)


def _primitive(value: Any, ftype: FieldType, path: str) -> Any:
    base = ftype.base
    if base == "boolean":
        if not isinstance(value, bool):
            raise ValueError(f"{path}: expected true or false, got {value!r}")
        return value
    if base in _FLOATS:
        if isinstance(value, str):
            try:
                return float(value)  # YAML 1.1 reads '1e3' as a string
            except ValueError:
                pass
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{path}: expected a number ({base}), got {value!r}")
        return float(value)
    if base in _INT_RANGES:
        return _integer(value, base, path)
    if isinstance(value, (bool, dict, list)) or value is None:
        raise ValueError(f"{path}: expected a string, got {value!r}")
    text = str(value)
    if ftype.string_bound is not None and len(text) > ftype.string_bound:
        raise ValueError(f"{path}: string longer than its bound {ftype.string_bound}: {text!r}")
    return text


def _integer(value: Any, base: str, path: str) -> Any:
    if base == "octet" and isinstance(value, bytes) and len(value) == 1:
        return value
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{path}: expected an integer ({base}), got {value!r}")
    low, high = _INT_RANGES[base]
    if not low <= value <= high:
        raise ValueError(f"{path}: {value} is out of range for {base} [{low}, {high}]")
    return bytes([value]) if base == "octet" else value
