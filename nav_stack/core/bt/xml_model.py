"""A minimal XML element tree that remembers line numbers, read with ``xml.parsers.expat``.

Why not ``xml.etree``: its elements do not carry source positions, and every load error of a
behaviour tree must name the line. Comments and text are dropped; attribute order is kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from nav_stack.core.bt.errors import BtLoadError


@dataclass
class XmlElement:
    """One element: tag, attributes, children and where it starts in its file."""

    tag: str
    attrib: dict[str, str]
    line: int
    source: str
    children: list[XmlElement] = field(default_factory=list)

    def label(self) -> str:
        """``<Tag name="x">`` (or ``<Tag ID="x">``), used to name the element in messages."""
        for key in ("name", "ID"):
            if key in self.attrib:
                return f'<{self.tag} {key}="{self.attrib[key]}">'
        return f"<{self.tag}>"

    def error(self, reason: str) -> BtLoadError:
        """A load error located at this element."""
        return BtLoadError(reason, self.source, self.line, self.label())


def parse_xml_text(text: str, source: str = "<string>") -> XmlElement:
    """Parse ``text`` into an element tree; malformed XML raises BtLoadError with the line."""
    parser = expat.ParserCreate()
    stack: list[XmlElement] = []
    roots: list[XmlElement] = []

    def start(tag: str, attrib: dict[str, str]) -> None:
        element = XmlElement(tag, dict(attrib), parser.CurrentLineNumber, source)
        (stack[-1].children if stack else roots).append(element)
        stack.append(element)

    def end(_tag: str) -> None:
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        raise BtLoadError(f"malformed XML: {expat.errors.messages[exc.code]} (column {exc.offset + 1})",
                          source, exc.lineno) from None
    if not roots:
        raise BtLoadError("empty XML document", source)
    return roots[0]


def parse_xml_file(path: str | Path) -> XmlElement:
    """Read and parse a file; a missing file raises BtLoadError naming it."""
    file_path = Path(path)
    try:
        text = file_path.read_text(encoding="utf-8")
    except OSError as exc:
        raise BtLoadError(f"cannot read file: {exc.strerror}", str(file_path)) from None
    return parse_xml_text(text, str(file_path))
