"""Message ↔ plain values ↔ YAML: round trips over nested types and arrays, and precise errors."""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from ros_tools.convert import (
    dict_to_message,
    field_value,
    message_to_dict,
    message_to_yaml,
    parse_yaml,
    to_csv,
    yaml_to_message,
)


def test_nested_message_with_fixed_arrays_and_sequences_round_trips():
    from sensor_msgs.msg import CameraInfo

    msg = CameraInfo(height=480, width=640, distortion_model="plumb_bob")
    msg.header.frame_id = "camera"
    msg.header.stamp.sec, msg.header.stamp.nanosec = 12, 500
    msg.d = [0.1, -0.2, 0.0, 0.0, 0.3]
    msg.k = np.arange(9, dtype=np.float64)
    msg.roi.do_rectify = True

    plain = message_to_dict(msg)

    assert plain["header"] == {"stamp": {"sec": 12, "nanosec": 500}, "frame_id": "camera"}
    assert plain["k"] == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
    assert type(plain["k"][0]) is float  # plain Python, not numpy scalars (YAML can dump it)
    assert plain["d"] == pytest.approx([0.1, -0.2, 0.0, 0.0, 0.3])
    assert dict_to_message(CameraInfo, plain) == msg


def test_sequence_of_nested_messages_round_trips():
    from nav_msgs.msg import Path as PathMsg

    plain = {
        "header": {"frame_id": "map"},
        "poses": [
            {"header": {"frame_id": "map"}, "pose": {"position": {"x": float(i), "y": -1.5}}}
            for i in range(3)
        ],
    }
    msg = dict_to_message(PathMsg, plain)

    assert [p.pose.position.x for p in msg.poses] == [0.0, 1.0, 2.0]
    assert msg.poses[2].pose.orientation.w == 1.0  # unspecified fields keep their defaults
    assert dict_to_message(PathMsg, message_to_dict(msg)) == msg


def test_bounded_sequence_of_messages_and_bounded_strings_round_trip():
    from rcl_interfaces.msg import ParameterDescriptor
    from type_description_interfaces.msg import FieldType

    msg = dict_to_message(ParameterDescriptor, {
        "name": "speed", "floating_point_range": [{"from_value": 0, "to_value": 2.5, "step": 0.5}],
    })
    assert msg.floating_point_range[0].to_value == 2.5
    assert dict_to_message(ParameterDescriptor, message_to_dict(msg)) == msg

    field = dict_to_message(FieldType, {"nested_type_name": "pkg/msg/Thing"})
    assert message_to_dict(field)["nested_type_name"] == "pkg/msg/Thing"


def test_bytes_and_uint8_arrays_become_int_lists_and_back():
    from sensor_msgs.msg import Image
    from std_msgs.msg import Byte, ByteMultiArray

    octets = dict_to_message(ByteMultiArray, {"data": [0, 7, 255]})
    assert octets.data == [b"\x00", b"\x07", b"\xff"]
    assert message_to_dict(octets)["data"] == [0, 7, 255]

    image = dict_to_message(Image, {"data": b"\x01\x02\x03", "width": 3})
    assert message_to_dict(image)["data"] == [1, 2, 3]
    assert dict_to_message(Image, message_to_dict(image)) == image

    assert message_to_dict(dict_to_message(Byte, {"data": 200})) == {"data": 200}


def test_builtin_time_and_duration_are_nested_sec_nanosec():
    from builtin_interfaces.msg import Duration, Time
    from std_msgs.msg import Header

    assert message_to_dict(Duration(sec=-3, nanosec=10)) == {"sec": -3, "nanosec": 10}
    header = yaml_to_message(Header, "{stamp: {sec: 5, nanosec: 6}, frame_id: odom}")
    assert header.stamp == Time(sec=5, nanosec=6)


def test_now_and_auto_stamp_with_the_given_clock():
    from builtin_interfaces.msg import Time
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import Header

    now = Time(sec=42, nanosec=7)
    stamped = yaml_to_message(PoseStamped, "{header: auto}", now=lambda: now)
    assert stamped.header.stamp == now
    header = yaml_to_message(Header, "{stamp: now, frame_id: map}", now=lambda: now)
    assert (header.stamp, header.frame_id) == (now, "map")


def test_constants_are_not_fields():
    from sensor_msgs.msg import BatteryState

    plain = message_to_dict(BatteryState())
    assert "POWER_SUPPLY_STATUS_CHARGING" not in plain
    assert "power_supply_status" in plain


def test_yaml_round_trip_keeps_field_order_and_special_floats():
    from sensor_msgs.msg import LaserScan

    scan = LaserScan(angle_min=-math.pi, range_max=3.5)
    scan.ranges = [1.0, math.inf, 0.25]
    text = message_to_yaml(scan)

    assert text.index("header:") < text.index("angle_min:") < text.index("ranges:")
    assert "- .inf" in text
    assert yaml_to_message(LaserScan, text) == scan


def test_no_arr_summarises_arrays_like_ros2_echo():
    from sensor_msgs.msg import CameraInfo, LaserScan

    scan = LaserScan()
    scan.ranges = [1.0] * 360
    assert message_to_dict(scan, no_arr=True)["ranges"] == "<sequence type: float, length: 360>"
    assert message_to_dict(CameraInfo(), no_arr=True)["k"] == "<array type: double[9]>"


def test_field_value_walks_a_dotted_path():
    from geometry_msgs.msg import PoseStamped

    msg = yaml_to_message(PoseStamped, "{pose: {position: {x: 1.5}}}")
    assert field_value(msg, "pose.position.x") == 1.5
    assert field_value(msg, "pose.position") == {"x": 1.5, "y": 0.0, "z": 0.0}
    with pytest.raises(ValueError, match=r"'geometry_msgs/msg/PoseStamped.pose' has no field 'positon'"):
        field_value(msg, "pose.positon")


def test_to_csv_flattens_depth_first():
    from geometry_msgs.msg import Twist

    msg = yaml_to_message(Twist, "{linear: {x: 0.5}, angular: {z: -1.0}}")
    assert to_csv(message_to_dict(msg)) == "0.5,0.0,0.0,0.0,0.0,-1.0"


def test_empty_yaml_gives_the_default_message():
    from geometry_msgs.msg import Twist

    assert yaml_to_message(Twist, "") == Twist()
    assert yaml_to_message(Twist, "{}") == Twist()


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("{linear: {x: 1}, angle: {}}", r"msg/Twist: no field 'angle' \(fields: linear, angular\)"),
        ("{linear: {x: fast}}", r"msg/Twist.linear.x: expected a number \(double\), got 'fast'"),
        ("{linear: 3}", r"geometry_msgs/msg/Twist.linear: expected a mapping of field names"),
        ("[1, 2]", r"geometry_msgs/msg/Twist: expected a mapping of field names"),
    ],
)
def test_wrong_values_name_the_field(text, error):
    from geometry_msgs.msg import Twist

    with pytest.raises(ValueError, match=error):
        yaml_to_message(Twist, text)


@pytest.mark.parametrize(
    ("values", "error"),
    [
        ({"k": [1.0, 2.0]}, r"CameraInfo.k: double\[9\] needs exactly 9 values, got 2"),
        ({"height": -1}, r"CameraInfo.height: -1 is out of range for uint32"),
        ({"height": 2.5}, r"CameraInfo.height: expected an integer \(uint32\), got 2.5"),
        ({"roi": {"do_rectify": 1}}, r"CameraInfo.roi.do_rectify: expected true or false, got 1"),
        ({"d": 0.5}, r"CameraInfo.d: expected a list for sequence<double>, got 0.5"),
        ({"distortion_model": None}, r"CameraInfo.distortion_model: expected a string, got None"),
    ],
)
def test_wrong_types_ranges_and_lengths_are_rejected(values, error):
    from sensor_msgs.msg import CameraInfo

    with pytest.raises(ValueError, match=error):
        dict_to_message(CameraInfo, values)


def test_bounded_sequences_and_strings_enforce_their_bounds():
    from rcl_interfaces.msg import ParameterDescriptor
    from type_description_interfaces.msg import FieldType

    with pytest.raises(ValueError, match=r"floating_point_range: .* holds at most 1 values, got 2"):
        dict_to_message(ParameterDescriptor, {"floating_point_range": [{}, {}]})
    with pytest.raises(ValueError, match=r"nested_type_name: string longer than its bound 255"):
        dict_to_message(FieldType, {"nested_type_name": "x" * 256})
    with pytest.raises(ValueError, match=r"floating_point_range\[0\].step: expected a number"):
        dict_to_message(ParameterDescriptor, {"floating_point_range": [{"step": "big"}]})


@pytest.mark.parametrize("text", ["{data: [1, 2", "data: {", "a: b: c", "{data: 'x}"])
def test_malformed_yaml_is_one_line_with_a_position(text):
    with pytest.raises(ValueError, match=r"^malformed YAML .*\(line \d+, column \d+\)$") as caught:
        parse_yaml(text)
    assert "\n" not in str(caught.value)


def _installed_message_classes() -> list[type]:
    share = Path(sys.prefix) / "share"
    classes = []
    for definition in sorted(share.glob("*/msg/*.msg")):
        package = definition.parents[1].name
        try:
            module = importlib.import_module(f"{package}.msg")
        except ImportError:
            continue
        cls = getattr(module, definition.stem, None)
        if cls is not None:
            classes.append(cls)
    return classes


def test_every_installed_message_type_round_trips_through_yaml():
    classes = _installed_message_classes()
    assert len(classes) > 100, "expected the common_interfaces message packages to be installed"
    for cls in classes:
        msg = cls()
        assert yaml_to_message(cls, message_to_yaml(msg)) == msg, cls
