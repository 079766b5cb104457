"""Port declarations (BT.CPP ``providedPorts``) and the string conversions of literal values.

A node class declares its ports once, as a tuple returned by the ``provided_ports`` classmethod:

    @classmethod
    def provided_ports(cls) -> PortList:
        return (input_port("loc", str, required=True), output_port("path", object))

In the XML a port is either a literal (converted with the port's type when the tree is loaded,
so ``hz="fast"`` fails at load, not at the first tick) or a blackboard pointer ``{key}``;
``{@key}`` addresses the root blackboard and ``{=}`` means "the key named like the port".
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

Converter = Callable[[str], Any]


class PortDirection(enum.Enum):
    """Data-flow direction of a port (``BT::PortDirection``)."""

    INPUT = "input"
    OUTPUT = "output"
    INOUT = "inout"


class _Missing:
    """Sentinel type for 'no default value'."""

    def __repr__(self) -> str:
        return "MISSING"


MISSING: Any = _Missing()

_TRUE = frozenset({"true", "True", "TRUE", "1"})
_FALSE = frozenset({"false", "False", "FALSE", "0"})


def to_bool(text: str) -> bool:
    """BT.CPP's ``convertFromString<bool>``: true/True/TRUE/1 and false/False/FALSE/0."""
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    raise ValueError(f"'{text}' is not a boolean (true/false/1/0)")


def semicolon_list(item: Converter) -> Converter:
    """Converter for BT.CPP vector ports written ``"a;b;c"`` (empty items are dropped)."""

    def convert(text: str) -> tuple[Any, ...]:
        return tuple(item(part.strip()) for part in text.split(";") if part.strip())

    return convert


_DEFAULT_CONVERTERS: dict[type, Converter] = {str: str, int: int, float: float, bool: to_bool}


@dataclass(frozen=True)
class PortInfo:
    """One declared port.

    Attributes:
        name: attribute name in the XML.
        direction: input, output or inout.
        type_: Python type of the value; decides the literal converter and documents the port.
        default: value used when the XML omits the port; a string default is parsed like an XML
            attribute (so ``"{goal}"`` makes a default blackboard pointer), other values are used as is.
        description: one line for people and for exported models.
        required: the XML must give this port (checked at load).
        converter: string → value; defaults to the converter of ``type_`` (str, int, float, bool).
    """

    name: str
    direction: PortDirection
    type_: type = str
    default: Any = MISSING
    description: str = ""
    required: bool = False
    converter: Converter | None = None

    @property
    def has_default(self) -> bool:
        """True when the port has a default value."""
        return self.default is not MISSING

    def convert(self, text: str) -> Any:
        """Convert a literal string to the port's type; raises ValueError when impossible."""
        converter = self.converter or _DEFAULT_CONVERTERS.get(self.type_)
        if converter is None:
            raise ValueError(f"a literal cannot be converted to {self.type_.__name__}; use a {{key}} pointer")
        try:
            return converter(text)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"'{text}' is not a valid {self.type_.__name__}: {exc}") from exc


PortList = tuple[PortInfo, ...]


def input_port(name: str, type_: type = str, default: Any = MISSING, description: str = "",
               *, required: bool = False, converter: Converter | None = None) -> PortInfo:
    """Declare an input port (``BT::InputPort``)."""
    return PortInfo(name, PortDirection.INPUT, type_, default, description, required, converter)


def output_port(name: str, type_: type = object, default: Any = MISSING, description: str = "") -> PortInfo:
    """Declare an output port (``BT::OutputPort``); a string default such as ``"{path}"`` wires it."""
    return PortInfo(name, PortDirection.OUTPUT, type_, default, description)


def bidirectional_port(name: str, type_: type = object, default: Any = MISSING, description: str = "",
                       *, required: bool = False, converter: Converter | None = None) -> PortInfo:
    """Declare an inout port (``BT::BidirectionalPort``)."""
    return PortInfo(name, PortDirection.INOUT, type_, default, description, required, converter)


def blackboard_key(value: str) -> str | None:
    """The key of a ``{key}`` pointer, or None for a literal. ``{=}`` returns ``"="``."""
    text = value.strip()
    if len(text) >= 3 and text[0] == "{" and text[-1] == "}":
        return text[1:-1].strip()
    return None
