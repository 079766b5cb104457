"""Schema text for MCAP: a type's .msg text plus every nested definition once, rosbag2 style."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from navsuite_tools.bag.schema import SEPARATOR, message_definition, msg_file_text

ODOMETRY_NESTED = [  # rosbag2 order: each type's dependencies sorted by name, depth first
    "geometry_msgs/PoseWithCovariance",
    "geometry_msgs/Pose",
    "geometry_msgs/Point",
    "geometry_msgs/Quaternion",
    "geometry_msgs/TwistWithCovariance",
    "geometry_msgs/Twist",
    "geometry_msgs/Vector3",
    "std_msgs/Header",
    "builtin_interfaces/Time",
]


def _sections(text: str) -> tuple[str, list[tuple[str, str]]]:
    parts = text.split(f"\n{SEPARATOR}\n")
    nested = []
    for part in parts[1:]:
        header, _, body = part.partition("\n")
        assert header.startswith("MSG: "), header
        nested.append((header[len("MSG: "):], body))
    return parts[0], nested


def _msg_file(type_name: str) -> str:
    package, name = type_name.split("/")
    return (Path(sys.prefix) / "share" / package / "msg" / f"{name}.msg").read_text()


def test_odometry_definition_has_each_nested_type_once_in_stable_order():
    text = message_definition("nav_msgs/msg/Odometry")
    root, nested = _sections(text)
    assert root == _msg_file("nav_msgs/Odometry")
    assert [name for name, _ in nested] == ODOMETRY_NESTED
    for name, body in nested:
        assert body == _msg_file(name), name
    assert message_definition("nav_msgs/Odometry") == text


def test_sequence_field_types_are_nested_too():
    _, nested = _sections(message_definition("tf2_msgs/msg/TFMessage"))
    names = [name for name, _ in nested]
    assert names[0] == "geometry_msgs/TransformStamped"
    assert {"geometry_msgs/Transform", "geometry_msgs/Vector3", "std_msgs/Header"} <= set(names)
    assert len(names) == len(set(names))


def test_flat_type_has_no_sections():
    assert SEPARATOR not in message_definition("std_msgs/msg/String")


def test_missing_definition_names_the_paths_tried(tmp_path):
    with pytest.raises(ValueError, match=r"no message definition for 'nav_msgs/msg/Odometry'.*Odometry\.msg"):
        msg_file_text("nav_msgs/Odometry", [tmp_path])


def test_malformed_type_name_is_rejected():
    with pytest.raises(ValueError, match="not a type name"):
        message_definition("Odometry")
