"""One robot's Nav2 stack in its own namespace: its parameter files and its remapping rules.

Why: in a fleet every node of robot N lives under ``/robotN`` (Nav2 Jazzy's cloned multi-robot
bringup), and one parameter file serves every robot. nav2_bringup makes that work in two steps,
restated here for nav-bringup's component processes:

* **Parameter files**: every ``<robot_namespace>`` in the text becomes ``/robotN`` (nav2_common's
  ReplaceString, which Jazzy's ``nav2_multirobot_params_all.yaml`` relies on for its scan topics),
  then the whole file is nested under the key ``robotN`` (RewrittenYaml's ``root_key``), so that a
  section ``amcl:`` reaches the node ``/robotN/amcl`` and ``local_costmap: local_costmap:`` reaches
  ``/robotN/local_costmap/local_costmap``. Wildcard sections (``/**``) stay at the top: they reach
  every node of the process, which are all this robot's.
* **Remaps**: Nav2's launch maps ``/tf`` and ``/tf_static`` to the relative ``tf`` and ``tf_static``,
  so that TF travels on ``/robotN/tf``. The rules here name ``/robotN/tf`` outright: the costmap
  nodes sit one level deeper (``/robotN/local_costmap``), where a relative ``tf`` would resolve to
  ``/robotN/local_costmap/tf``; the outcome for every other node is Nav2's. Two more global topics
  of this stack move into the namespace, each for a reason: ``/diagnostics`` (the controller's
  localization guard reads AMCL's ``amcl: localization`` status there, and must not read another
  robot's), and MPPI's ``/trajectories``. Bonds need no rule: their topic is the relative ``bond``,
  as Nav2's.

A fleet's parameter files should not name a topic by an absolute name outside the robot's namespace
(``topic: /scan`` reads no robot's scan); :func:`foreign_topics` finds such settings for a warning.

Pure: yaml and the standard library only; no rclpy.
"""

from __future__ import annotations

import tempfile
from collections.abc import Collection, Sequence
from pathlib import Path
from typing import Any

import yaml

from nav_stack.ros.bringup.param_files import WILDCARD, NavParams

PLACEHOLDER = "<robot_namespace>"
#: The global topics this stack's nodes name by absolute name that belong to one robot in a fleet.
ROBOT_GLOBAL_TOPICS = ("/tf", "/tf_static", "/diagnostics", "/trajectories")


def robot_namespace(name: str) -> str:
    """``/name`` for a robot name given with or without slashes (``robot1``, ``/robot1/``)."""
    stripped = name.strip("/")
    if not stripped:
        raise ValueError("a robot namespace must not be empty")
    return f"/{stripped}"


def namespaced_tree(text: str, namespace: str) -> dict[str, Any]:
    """A parameter file's text for ``namespace`` (``/robot1``): placeholders replaced, sections nested."""
    tree = yaml.safe_load(text.replace(PLACEHOLDER, namespace)) or {}
    if not isinstance(tree, dict):
        raise ValueError(f"expected a map of node names at the top level, got {tree!r}")
    wildcards = {key: value for key, value in tree.items() if str(key).strip("/").startswith(WILDCARD)}
    nodes = {key: value for key, value in tree.items() if key not in wildcards}
    root: dict[str, Any] = dict(wildcards)
    if nodes:
        root[namespace.strip("/")] = nodes
    return root


def namespaced_files(files: Sequence[str | Path], namespace: str, directory: str | None = None) -> list[str]:
    """Each file rewritten for ``namespace`` (:func:`namespaced_tree`) into a temporary file; their paths.

    The caller deletes them (the process that runs the nodes, once rclpy has read them).
    """
    out = []
    for path in files:
        tree = namespaced_tree(Path(path).read_text(), namespace)
        with tempfile.NamedTemporaryFile("w", prefix=f"nav_bringup_{namespace.strip('/').replace('/', '_')}_",
                                         suffix=".yaml", dir=directory, delete=False) as handle:
            yaml.safe_dump(tree, handle, sort_keys=False)
        out.append(handle.name)
    return out


def namespace_remaps(namespace: str) -> list[str]:
    """The rcl remap rules (``-r`` operands) that move the robot's global topics under ``namespace``."""
    return [f"{topic}:={namespace}{topic}" for topic in ROBOT_GLOBAL_TOPICS]


def foreign_topics(files: Sequence[str | Path], namespace: str, running: Collection[str]) -> list[str]:
    """``<node>: <key>: <value>`` of every topic setting of a ``running`` node (fully qualified section
    names: ``amcl``, ``local_costmap/local_costmap``) with an absolute name outside ``namespace`` once
    placeholders are replaced (``topic: /scan`` in a fleet: no robot publishes there)."""
    params = NavParams(files)
    found = []
    for node in (node for node in params.nodes if node in running):
        for key, setting in params.section(node).items():
            value = setting.value
            if not (key.endswith("topic") and isinstance(value, str) and value.startswith("/")):
                continue
            resolved = value.replace(PLACEHOLDER, namespace)
            if resolved != namespace and not resolved.startswith(f"{namespace}/"):
                found.append(f"{node}: {key}: {value}")
    return found
