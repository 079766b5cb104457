"""Message definitions for MCAP schemas, assembled from the installed ``.msg`` files.

rosbag2 (``rosbag2_storage_mcap``) stores one schema per message type: schema name
``pkg/msg/Type``, encoding ``ros2msg``, and as data the type's ``.msg`` text followed, for every
nested message type, by a line of 80 ``=``, a line ``MSG: pkg/Type`` and that type's text. Readers
(Foxglove, Lichtblick, ``ros2 bag``, ``mcap_ros2``) parse the CDR bytes with it, so it must be
complete. We build the same text rosbag2 would: each type's direct dependencies sorted by name,
visited depth first, every type written once.

The Jazzy wheels and our built interface packages install the ``.msg`` files under
``<prefix>/share/<pkg>/msg/``; the prefixes searched are ``sys.prefix`` and then the entries of
``AMENT_PREFIX_PATH``. Dependencies come from the generated Python class
(``get_fields_and_field_types``), which knows nested types without parsing ``.msg`` syntax.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from ros_tools.types import import_type, parse_field_type, parse_type_name

#: The line that separates nested definitions (80 '=' signs, the ROS 1 / rosbag2 convention).
SEPARATOR = "=" * 80
SCHEMA_ENCODING = "ros2msg"


def default_prefixes() -> tuple[Path, ...]:
    """Install prefixes searched for ``share/<pkg>/msg/*.msg``: the venv, then AMENT_PREFIX_PATH."""
    prefixes = [Path(sys.prefix)]
    for entry in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if entry and Path(entry) not in prefixes:
            prefixes.append(Path(entry))
    return tuple(prefixes)


def msg_file_text(type_name: str, prefixes: Sequence[Path] | None = None) -> str:
    """The text of one type's ``.msg`` file.

    Raises:
        ValueError: malformed type name, or no ``.msg`` file under any prefix (the paths tried
            are named).
    """
    parsed = parse_type_name(type_name, "msg")
    relative = Path("share", parsed.package, "msg", f"{parsed.name}.msg")
    tried = []
    for prefix in prefixes if prefixes is not None else default_prefixes():
        path = prefix / relative
        if path.is_file():
            return path.read_text(encoding="utf-8")
        tried.append(str(path))
    raise ValueError(f"no message definition for '{parsed}': none of {', '.join(tried)} exists")


def nested_types(type_name: str) -> list[str]:
    """The message types a type's fields use directly, as sorted ``pkg/Type`` names."""
    cls = import_type(type_name, "msg")
    found = set()
    for text in cls.get_fields_and_field_types().values():
        field = parse_field_type(text)
        if field.is_message:
            found.add(field.base)
    return sorted(found)


def _short(type_name: str) -> str:
    parsed = parse_type_name(type_name, "msg")
    return f"{parsed.package}/{parsed.name}"


@functools.lru_cache(maxsize=256)
def _cached_definition(type_name: str, prefixes: tuple[Path, ...]) -> str:
    seen: set[str] = set()

    def append(name: str) -> str:
        text = msg_file_text(name, prefixes)
        for dependency in nested_types(name):
            if dependency not in seen:
                seen.add(dependency)
                text += f"\n{SEPARATOR}\nMSG: {dependency}\n" + append(dependency)
        return text

    return append(_short(type_name))


def message_definition(type_name: str, prefixes: Sequence[Path] | None = None) -> str:
    """The full ``ros2msg`` definition of a message type (``pkg/msg/Type`` or ``pkg/Type``).

    Raises:
        ValueError: unknown type, or a ``.msg`` file of it or of a nested type is missing.
    """
    chosen = tuple(prefixes) if prefixes is not None else default_prefixes()
    return _cached_definition(str(parse_type_name(type_name, "msg")), chosen)
