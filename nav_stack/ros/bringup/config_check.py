"""Check a user's Nav2 parameter files against what this stack can run, before anything starts.

Why: a Nav2 user's first step is to bring their own ``nav2_params.yaml``. When it names a plugin this
stack does not have (a controller, a costmap layer, a behavior) or asks a lifecycle manager for a
server the stack lacks, the node that meets it fails its configure seconds into the launch, with one
problem at a time. This check reads the files the way rcl will (nav_stack/ros/bringup/param_files.py),
collects every such problem, and nav-bringup refuses the files with one message that names, for each
problem, the file, the section, the key, the value and what is supported.

Pure: no rclpy.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nav_stack.ros.bringup.param_files import NavParams
from nav_stack.ros.bringup.plugin_catalog import (
    AVAILABLE_NODES,
    PLUGIN_LISTS,
    TYPE_PARAMETERS,
    PluginList,
    class_name,
)


@dataclass(frozen=True)
class Problem:
    """One thing in a parameter file that the stack cannot run."""

    file: Path | None  # None: a default of the stack, not a value of any file
    section: str
    key: str
    value: Any
    reason: str
    supported: tuple[str, ...] = ()

    def __str__(self) -> str:
        where = f"{self.file}: " if self.file else ""
        supported = f" (supported: {', '.join(self.supported)})" if self.supported else ""
        setting = f"{self.key}: {self.value!r} " if self.key else ""
        return f"{where}{self.section}: {setting}{self.reason}{supported}"


class ConfigError(ValueError):
    """Parameter files the stack cannot run; ``problems`` lists every reason."""

    def __init__(self, files: Sequence[Path], problems: Sequence[Problem]) -> None:
        self.problems = tuple(problems)
        names = ", ".join(str(f) for f in files)
        lines = "\n".join(f"  - {problem}" for problem in self.problems)
        super().__init__(f"{names}: {len(self.problems)} setting(s) this stack cannot run:\n{lines}\n"
                         "Change or remove these settings (README: 'Differences from Nav2' lists what "
                         "this stack supports).")


def _ids(params: NavParams, spec: PluginList) -> list[str]:
    value = params.get(spec.node, spec.key, list(spec.default))
    if isinstance(value, str):
        return [v for v in value.replace(",", " ").split() if v]
    return [str(v) for v in value or []]


def _check_list(params: NavParams, spec: PluginList) -> list[Problem]:
    problems = []
    defaults = dict(spec.default_types)
    for plugin_id in _ids(params, spec):
        key = f"{plugin_id}.{spec.type_key}"
        plugin_type = params.get(spec.node, key)
        if plugin_type is None:
            if plugin_id not in defaults:
                problems.append(Problem(params.where(spec.node, spec.key), spec.node, key, None,
                                        f"is not set: '{plugin_id}' (listed in {spec.key}) needs a type",
                                        spec.supported))
            continue
        if class_name(plugin_type) not in spec.supported:
            problems.append(Problem(params.where(spec.node, key), spec.node, key, plugin_type,
                                    "is not a plugin this stack has", spec.supported))
    return problems


def check_plugins(params: NavParams, nodes: Sequence[str]) -> list[Problem]:
    """Every plugin type, among the servers ``nodes`` that will run, that the stack does not have.

    The costmaps are checked with the server that owns them (controller_server: local_costmap,
    planner_server: global_costmap).
    """
    running = set(nodes)
    if "controller_server" in running:
        running.add("local_costmap/local_costmap")
    if "planner_server" in running:
        running.add("global_costmap/global_costmap")
    problems: list[Problem] = []
    for spec in PLUGIN_LISTS:
        if spec.node in running:
            problems.extend(_check_list(params, spec))
    for node, key, default, supported in TYPE_PARAMETERS:
        value = params.get(node, key, default)
        if node in running and class_name(value) not in supported:
            problems.append(Problem(params.where(node, key), node, key, value,
                                    "is not a type this stack has", supported))
    return problems


def check_node_names(params: NavParams, manager: str, names: Sequence[str]) -> list[Problem]:
    """Servers a lifecycle manager is asked to run that the stack does not have: named by the file's
    ``node_names``, or, when bringup chose the list, configured by a section of their own."""
    missing = [name for name in names if name not in AVAILABLE_NODES]
    servers = tuple(sorted(AVAILABLE_NODES))
    if params.get(manager, "node_names") is not None:
        return [Problem(params.where(manager, "node_names"), manager, "node_names", name,
                        "is not a server this stack has", servers) for name in missing]
    return [Problem(params.section_file(name), name, "", None,
                    "this server is configured, but the stack has no such server", servers)
            for name in missing]
