"""Helpers for the localization-side nav_stack integration tests (map_server, amcl, managers, saver)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rclpy.client import Client
from rclpy.executors import Executor

from navsuite_testing.ros import REPO, spin_until, spinning
from ros_tools.runtime.requests import SERVICE_RETRY_S, call_until_answered

MAP_YAML = REPO / "maps" / "turtlebot3_world.yaml"


def call(executor: Executor, client: Client, request: Any, timeout: float = 10.0,
         resend_after: float | None = SERVICE_RETRY_S) -> Any:
    """Call a service from a test, spinning ``executor`` until the answer arrives (bounded waits;
    the request is sent again while unanswered unless ``resend_after`` is None, see
    ros_tools.runtime.requests)."""
    spin_until(executor, client.service_is_ready, timeout, f"service {client.srv_name}")
    return call_until_answered(client, request, timeout, spinning(executor), resend_after)


def write_map_yaml(path: Path, **fields: object) -> Path:
    """A map yaml with the turtlebot3_world image and the given fields replaced (None removes one)."""
    import yaml

    doc: dict[str, object] = yaml.safe_load(MAP_YAML.read_text())
    doc["image"] = str(MAP_YAML.parent / str(doc["image"]))
    for key, value in fields.items():
        if value is None:
            doc.pop(key, None)
        else:
            doc[key] = value
    path.write_text(yaml.safe_dump(doc))
    return path
