"""``interface show|list|packages|package``: interface definitions from the installed share/ files.

The message wheels (and our own interface build) install ``share/<pkg>/<kind>/<Name>.<kind>`` and
register their interfaces in the ament resource index
(``share/ament_index/resource_index/rosidl_interfaces/<pkg>``). ``show`` prints a definition
with its comments and expands every nested type below the field that uses it, indented by a tab
and without comments, as ``ros2 interface show`` does. These verbs need no ROS graph.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import sys
from pathlib import Path
from typing import Any

from navsuite_tools.cli.common import CliError, add_command
from ros_tools.types import KINDS, PRIMITIVES, parse_type_name

_KIND_TITLES = {"msg": "Messages", "srv": "Services", "action": "Actions"}
#: Primitive names as .msg files spell them (which differ from the IDL names in PRIMITIVES).
_MSG_PRIMITIVES = frozenset({"bool", "byte", "float32", "float64", "time", "duration"})
_FIELD_TYPE_RE = re.compile(r"^([A-Za-z][A-Za-z0-9_/]*)")


def register(subparsers: Any) -> None:
    """Add ``interface`` and its verbs to the top-level parser."""
    verbs = add_command(subparsers, "interface", "show interface definitions")

    p = verbs.add_parser("show", help="print an interface definition, nested types expanded")
    p.add_argument("type", help="e.g. nav2_msgs/action/NavigateToPose or geometry_msgs/Pose")
    p.add_argument("--no-comments", action="store_true", help="leave out comments")
    p.set_defaults(handler=run_show, offline=True)

    p = verbs.add_parser("list", help="list every installed interface")
    p.set_defaults(handler=run_list, offline=True)

    p = verbs.add_parser("packages", help="list the packages that define interfaces")
    p.set_defaults(handler=run_packages, offline=True)

    p = verbs.add_parser("package", help="list the interfaces of one package")
    p.add_argument("package_name")
    p.set_defaults(handler=run_package, offline=True)


def share_prefixes() -> list[Path]:
    """Install prefixes to search: AMENT_PREFIX_PATH, then the running Python's prefix."""
    prefixes = [Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(Path(sys.prefix))
    return list(dict.fromkeys(prefixes))


def _package_prefix(package: str) -> Path | None:
    """The prefix a package's Python module was installed under (``<prefix>/lib/pythonX/site-packages``)."""
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        return None
    if spec is None or spec.origin is None:
        return None
    parents = Path(spec.origin).resolve().parents
    return parents[4] if len(parents) > 4 else None


def definition_path(type_text: str) -> Path:
    """The installed definition file of ``pkg/kind/Name`` (short ``pkg/Name`` tries msg, srv, action).

    Raises:
        CliError: malformed name or no definition file installed for it.
    """
    kinds = [k for k in KINDS if f"/{k}/" in type_text] or list(KINDS)
    candidates: list[Path] = []
    for kind in kinds:
        try:
            name = parse_type_name(type_text, kind)
        except ValueError as exc:
            raise CliError(str(exc)) from None
        prefixes = share_prefixes()
        extra = _package_prefix(name.package)
        if extra is not None:
            prefixes.append(extra)
        candidates += [p / "share" / name.package / kind / f"{name.name}.{kind}" for p in prefixes]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    raise CliError(f"Unknown interface type '{type_text}': no definition file installed for it")


def _strip_comment(line: str) -> str:
    quote = None
    for index, char in enumerate(line):
        if char in "'\"":
            quote = None if quote == char else (quote or char)
        elif char == "#" and quote is None:
            return line[:index].rstrip()
    return line.rstrip()


def _nested_type(code: str, package: str) -> str | None:
    """The ``pkg/Name`` a field line refers to, or None for primitives, constants and blank lines."""
    match = _FIELD_TYPE_RE.match(code.strip())
    if match is None or "=" in code.split(None, 1)[-1]:
        return None
    base = match.group(1)
    if base in PRIMITIVES or base in _MSG_PRIMITIVES:
        return None
    if base == "Header":
        return "std_msgs/Header"
    return base if "/" in base else f"{package}/{base}"


def render_definition(text: str, package: str, indent: str = "", comments: bool = True) -> list[str]:
    """Definition lines with each nested message's definition expanded below its field."""
    lines: list[str] = []
    for raw in text.splitlines():
        code = _strip_comment(raw)
        if comments:
            lines.append(f"{indent}{raw.rstrip()}")
        elif code:
            lines.append(f"{indent}{code}")
        nested = _nested_type(code, package) if code and code != "---" else None
        if nested is not None:
            nested_path = definition_path(f"{nested.split('/')[0]}/msg/{nested.split('/')[-1]}")
            lines += render_definition(nested_path.read_text(), nested.split("/")[0], indent + "\t", False)
    return lines


def run_show(args: argparse.Namespace, _session: None) -> int:
    """``interface show``: the definition text, nested types expanded."""
    path = definition_path(args.type)
    package = path.parents[1].name
    for line in render_definition(path.read_text(), package, comments=not args.no_comments):
        print(line)
    return 0


def installed_interfaces() -> dict[str, list[str]]:
    """Package → sorted ``pkg/kind/Name`` entries, from the ament resource index."""
    found: dict[str, set[str]] = {}
    for prefix in share_prefixes():
        index = prefix / "share" / "ament_index" / "resource_index" / "rosidl_interfaces"
        for marker in sorted(index.glob("*")) if index.is_dir() else []:
            for entry in marker.read_text().split():
                kind, _, file_name = entry.partition("/")
                stem, _, extension = file_name.rpartition(".")
                if kind in KINDS and extension == kind:
                    found.setdefault(marker.name, set()).add(f"{marker.name}/{kind}/{stem}")
    return {package: sorted(names) for package, names in sorted(found.items())}


def run_list(_args: argparse.Namespace, _session: None) -> int:
    """``interface list``: every interface grouped into Messages, Services and Actions."""
    everything = [name for names in installed_interfaces().values() for name in names]
    for kind, title in _KIND_TITLES.items():
        print(f"{title}:")
        for name in everything:
            if name.split("/")[1] == kind:
                print(f"    {name}")
    return 0


def run_packages(_args: argparse.Namespace, _session: None) -> int:
    """``interface packages``: packages that define interfaces."""
    for package in installed_interfaces():
        print(package)
    return 0


def run_package(args: argparse.Namespace, _session: None) -> int:
    """``interface package``: the interfaces of one package."""
    names = installed_interfaces().get(args.package_name)
    if not names:
        raise CliError(f"Unknown package '{args.package_name}': it defines no installed interfaces")
    for name in names:
        print(name)
    return 0
