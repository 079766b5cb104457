"""Nav2 parameters accepted and never read are said once per node at startup, with name and value."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import pytest
from rclpy.parameter import Parameter

from nav_stack.ros.common.params import declare_dataclass

pytestmark = pytest.mark.ros


@dataclass(frozen=True)
class Layer:
    enabled: bool = True
    subscribe_to_updates: bool = False

    IGNORED: ClassVar[dict[str, str]] = {"subscribe_to_updates": "no map_updates here"}


@dataclass(frozen=True)
class Plain:
    enabled: bool = True


class _Recorder:
    def __init__(self) -> None:
        self.warnings: list[str] = []

    def warning(self, text: str) -> None:
        self.warnings.append(text)

    def info(self, text: str) -> None:  # pragma: no cover - the binder logs nothing else
        pass


def test_ignored_parameters_warned_once_with_prefix_name_value_and_reason(ros_context):
    import rclpy

    node = rclpy.create_node("ignored_probe", context=ros_context,
                             parameter_overrides=[Parameter("static_layer.subscribe_to_updates", value=True)])
    recorder = _Recorder()
    node.get_logger = lambda: recorder  # type: ignore[method-assign]
    try:
        declare_dataclass(node, Layer, "static_layer.")
        declare_dataclass(node, Layer, "static_layer.")  # a second configure: no second warning
        declare_dataclass(node, Plain, "other.")         # nothing ignored: nothing said
        assert recorder.warnings == [
            "parameters accepted for Nav2 compatibility and not read: "
            "static_layer.subscribe_to_updates=True (no map_updates here)"]
        declare_dataclass(node, Layer, "global_layer.")   # the same dataclass under another prefix
        assert len(recorder.warnings) == 2
        assert "global_layer.subscribe_to_updates=False" in recorder.warnings[1]
    finally:
        node.destroy_node()
