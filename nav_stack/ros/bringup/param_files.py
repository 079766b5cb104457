"""Nav2 parameter files read as rcl reads them: several files merged, per node, with flattened keys.

Why here and not through rclpy: nav-bringup must know what a user's files configure before it
starts a single process (which servers to run, which plugins they name) so that a file the stack
cannot run is refused at once with every problem listed, instead of a node failing its configure a
minute later. The rules follow rcl's YAML parser (rcl_yaml_param_parser):

* a section is ``<node>: {ros__parameters: {...}}``, where the keys above ``ros__parameters`` form
  the node's fully qualified name (``local_costmap: {local_costmap: ...}`` is
  ``/local_costmap/local_costmap``); ``/**`` (or ``/**/<name>``) applies to every node (of that name);
* nested maps below ``ros__parameters`` are flattened into dotted names (``FollowPath.plugin``);
* files given later override earlier ones, key by key.

Pure: yaml and the standard library only; no rclpy.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

PARAMS_KEY = "ros__parameters"
WILDCARD = "**"


class ParamFileError(ValueError):
    """A parameter file that cannot be read as a Nav2 parameter file (the message names the file)."""


@dataclass(frozen=True)
class Setting:
    """One parameter value and the file it came from."""

    value: Any
    file: Path


def _flatten(prefix: str, tree: Mapping[str, Any], out: dict[str, Any]) -> None:
    for key, value in tree.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            _flatten(f"{name}.", value, out)
        else:
            out[name] = value


def _sections(path: Path, tree: Any, namespace: tuple[str, ...] = ()) -> Iterable[tuple[str, dict[str, Any]]]:
    """(fully qualified node name without the leading '/', flattened parameters) of every section."""
    if not isinstance(tree, Mapping):
        where = "/".join(namespace) or "the top level"
        raise ParamFileError(f"{path}: {where}: expected a map of node names, got {tree!r}")
    for key, value in tree.items():
        key = str(key).strip("/")
        if key == PARAMS_KEY:
            if not isinstance(value, Mapping):
                where = f"{'/'.join(namespace)}.{PARAMS_KEY}"
                raise ParamFileError(f"{path}: {where}: expected a map, got {value!r}")
            flat: dict[str, Any] = {}
            _flatten("", value, flat)
            yield "/".join(namespace), flat
        elif value is not None:
            yield from _sections(path, value, (*namespace, *[k for k in key.split("/") if k]))


class NavParams:
    """The merged ``ros__parameters`` of one or more files.

    Node names are fully qualified without the leading slash (``controller_server``,
    ``local_costmap/local_costmap``).
    """

    def __init__(self, files: Sequence[Path | str]) -> None:
        self.files = tuple(Path(f) for f in files)
        self._nodes: dict[str, dict[str, Setting]] = {}
        self._first_file: dict[str, Path] = {}
        for path in self.files:
            try:
                tree = yaml.safe_load(path.read_text())
            except OSError as error:
                raise ParamFileError(f"{path}: cannot read it: {error.strerror or error}") from error
            except yaml.YAMLError as error:
                raise ParamFileError(f"{path}: not valid YAML: {error}") from error
            for node, flat in _sections(path, tree or {}):
                section = self._nodes.setdefault(node, {})
                self._first_file.setdefault(node, path)
                section.update({key: Setting(value, path) for key, value in flat.items()})

    def configures(self, node: str) -> bool:
        """Whether a file has a section of its own for ``node`` (wildcards do not count)."""
        return node in self._nodes

    def section(self, node: str) -> dict[str, Setting]:
        """Every parameter that reaches ``node``: wildcard sections first, then its own section."""
        name = node.rsplit("/", 1)[-1]
        merged: dict[str, Setting] = {}
        for pattern in (WILDCARD, f"{WILDCARD}/{name}", node):
            merged.update(self._nodes.get(pattern, {}))
        return merged

    def get(self, node: str, key: str, default: Any = None) -> Any:
        """The value of ``key`` for ``node``, or ``default``."""
        setting = self.section(node).get(key)
        return default if setting is None else setting.value

    def where(self, node: str, key: str) -> Path | None:
        """The file that set ``key`` for ``node`` (None: nobody set it)."""
        setting = self.section(node).get(key)
        return None if setting is None else setting.file

    def section_file(self, node: str) -> Path | None:
        """The first file with a section of its own for ``node`` (None: no file has one)."""
        return self._first_file.get(node)

    @property
    def nodes(self) -> tuple[str, ...]:
        """Every node with a section of its own, in the order the files first name them."""
        return tuple(node for node in self._nodes if not node.startswith(WILDCARD))
